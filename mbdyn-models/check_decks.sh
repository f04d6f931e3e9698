#!/usr/bin/env bash
# ctest: the committed decks are what the runner writes from the scenes, each deck declares as
# many nodes, bodies and joints as it defines (labels as in ../shared/data/mbdyn/README.md), and
# the runner says clearly when MBDyn is not installed (exit 3, deck still written).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "check_decks: $*" >&2; exit 1; }
"$root/mbdyn-models/run" "$root/scenes/isotropic_200rpm.scene" "$tmp/iso_200rpm" --netcdf --deck-only 2>/dev/null
"$root/mbdyn-models/run" "$root/scenes/c3zero_242rpm.scene" "$tmp/c3zero_242rpm_cyhalf" --deck-only 2>/dev/null
for d in iso_200rpm c3zero_242rpm_cyhalf; do
  diff -q "$tmp/$d.mbd" "$root/mbdyn-models/hammond/$d.mbd" >/dev/null ||
    fail "mbdyn-models/hammond/$d.mbd is out of date: regenerate it with mbdyn-models/run (see mbdyn-models/README.md)"
  deck="$root/mbdyn-models/hammond/$d.mbd"
  nodes=$(grep -c '^ *structural: ' "$deck"); bodies=$(grep -c '^ *body: ' "$deck"); joints=$(grep -c '^ *joint: ' "$deck")
  grep -q "structural nodes: $nodes;" "$deck" || fail "$d: $nodes structural nodes defined, control data disagrees"
  grep -q "rigid bodies: $bodies;" "$deck" || fail "$d: $bodies bodies defined, control data disagrees"
  grep -q "joints: $joints;" "$deck" || fail "$d: $joints joints defined, control data disagrees"
  for label in 21 22 23 24 31 32 33 34 2 3 4 5 6; do grep -q "joint: $label," "$deck" || fail "$d: joint $label missing"; done
  grep -q "method: ms, 0.6;" "$deck" || fail "$d: integrator is not multistep rho_inf 0.6"
done
grep -q "C_3 = 0;" "$root/mbdyn-models/hammond/c3zero_242rpm_cyhalf.mbd" || fail "c3zero deck: blade 3 damper not inoperative"
grep -q "C_Y = 25539.35;" "$root/mbdyn-models/hammond/c3zero_242rpm_cyhalf.mbd" || fail "c3zero deck: c_y is not 25539.35"
# A nonlinear-damper scene: the table reproduces eq. 39 at its nodes and is flat outside.
"$root/mbdyn-models/run" "$root/scenes/nonlinear_CL0.scene" "$tmp/nl" --deck-only 2>/dev/null
grep -q 'nlsf viscous, 0., "damper_1"' "$tmp/nl.mbd" || fail "nonlinear deck: no nlsf viscous damper"
# Without MBDyn: exit 3 and a clear message.
set +e
PATH=/usr/bin:/bin command -v mbdyn >/dev/null && { echo "check_decks: mbdyn installed, skipping the not-installed check"; exit 0; }
msg=$(PATH=/usr/bin:/bin "$root/mbdyn-models/run" "$root/scenes/c3zero_242rpm.scene" "$tmp/run" 2>&1); rc=$?
set -e
[ "$rc" = 3 ] || fail "runner without MBDyn: exit $rc, expected 3"
echo "$msg" | grep -q "MBDyn is not installed" || fail "runner without MBDyn: message '$msg'"
[ -s "$tmp/run.mbd" ] || fail "runner without MBDyn: no deck written"
echo "check_decks: decks in sync, counts consistent, runner reports missing MBDyn"
