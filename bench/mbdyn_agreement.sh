#!/usr/bin/env bash
# The README's figures on real MBDyn output and on the ad-hoc model, from the full runs.
#   bench/mbdyn_agreement.sh [BUILD_DIR] [MBDYN_DATA_DIR]
# MBDYN_DATA_DIR holds iso_200rpm/ and c3zero_242rpm_cyhalf/ (default ../shared/data/mbdyn).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
data="${2:-$here/../shared/data/mbdyn}"
mlce="$build/mlce"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# min/max of column 2 over the run and over t >= T (column 1 = time)
range() { awk -F, -v T="$2" 'NR>1 { if (a == "" || $2 < a) a = $2; if (b == "" || $2 > b) b = $2;
           if ($1 >= T) { if (c == "" || $2 < c) c = $2; if (d == "" || $2 > d) d = $2 } }
           END { printf "%.4f .. %.4f (whole run), %.4f .. %.4f (t >= %s)\n", a, b, c, d, T }' "$1"; }
# largest |column 2 - column 3|
maxdiff() { awk -F, 'NR>1 { d = $2 - $3; if (d < 0) d = -d; if (d > m) m = d } END { printf "%.3g\n", m }' "$1"; }

c3="$data/c3zero_242rpm_cyhalf/c3zero_242rpm_cyhalf"
"$mlce" extract "$c3" --channel rel:13:4:z --channel joint:33:14 > "$work/c3.csv"
echo "MBDyn c3zero_242rpm_cyhalf, blade 3 lag rel:13:4:z: $(range "$work/c3.csv" 20)"
echo "  |rel:13:4:z - joint:33:14| max: $(maxdiff "$work/c3.csv") rad"

"$mlce" simulate "$here/scenes/c3zero_242rpm.scene" --out "$work/adhoc" --quiet 2>/dev/null
"$mlce" extract "$work/adhoc" --channel rel:13:4:z > "$work/adhoc.csv"
echo "ad-hoc scenes/c3zero_242rpm.scene, blade 3 lag: $(range "$work/adhoc.csv" 20)"

"$mlce" simulate "$here/scenes/c3zero_124rpm.scene" --format columns --out "$work/low" --quiet 2>/dev/null
awk '!/^#/ { a = $4 < 0 ? -$4 : $4; if ($1 < 5 && a > e) e = a; if ($1 > 25 && a > l) l = a }
     END { printf "ad-hoc scenes/c3zero_124rpm.scene: max |zeta3| %.4f rad (t < 5 s), %.3g rad (t > 25 s)\n", e, l }' "$work/low.txt"
"$mlce" simulate "$here/scenes/c3zero_242rpm.scene" --cy 51078.7 --t_end 60 --format columns --out "$work/full" --quiet 2>/dev/null
awk '!/^#/ { a = $4 < 0 ? -$4 : $4; if ($1 < 10 && a > e) e = a; if ($1 > 50 && a > l) l = a }
     END { printf "ad-hoc 242.4 rpm with printed c_y = 51078.7: max |zeta3| %.4f (t < 10 s), %.4f (t > 50 s): rate %.4f 1/s\n", e, l, log(l / e) / 50 }' "$work/full.txt"

iso="$data/iso_200rpm/iso_200rpm"
"$mlce" extract "$iso" --channel joint:33:14 --channel node:2:x > "$work/t.csv"
"$mlce" extract "$iso.nc" --channel joint:33:14 --channel node:2:x > "$work/n.csv"
paste -d, "$work/t.csv" "$work/n.csv" | awk -F, 'NR>1 { for (c = 2; c <= 3; c++) { d = $c - $(c+3); d = d < 0 ? -d : d;
    s = $(c+3) < 0 ? -$(c+3) : $(c+3); if (s > 0 && d / s > m[c]) m[c] = d / s }
    if ($1 != $4 && ($1 - $4 > 1e-9 || $4 - $1 > 1e-9)) bad++ }
    END { printf "iso_200rpm text vs .nc: max relative difference joint:33:14 %.2g, node:2:x %.2g; time mismatches %d\n", m[2], m[3], bad }'
"$mlce" simulate "$here/scenes/isotropic_200rpm.scene" --out "$work/iso" --quiet 2>/dev/null
"$mlce" extract "$work/iso" --channel rel:13:4:z > "$work/iso_adhoc.csv"
paste -d, "$work/t.csv" "$work/iso_adhoc.csv" | awk -F, 'NR>1 { d = $2 - $5; d = d < 0 ? -d : d; if (d > m) m = d;
    p = $2 < 0 ? -$2 : $2; if (p > pk) pk = p } END { printf "iso_200rpm, blade 3 lag, ad-hoc vs MBDyn over 20 s: max difference %.3g rad (peak lag %.4f rad)\n", m, pk }'

# The MLCE of every blade's lag over the whole isotropic run, beside the slowest multiblade
# eigenvalue: the angles from two nodes' orientations (rel:A:B:z, from the .mov's degrees with 7
# digits) end in a few steps of that resolution, the damper's own angle (joint:L:14) in underflow.
field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2- | tr -d '"'; }
slowest="$("$mlce" eigen "$here/scenes/isotropic_200rpm.scene" --json | grep -o '"exponents":\[[^],]*' | cut -d[ -f2)"
echo "iso_200rpm, slowest multiblade eigenvalue (mlce eigen): $slowest 1/s; the MLCE of the whole run (mlce estimate --channel C):"
for ch in rel:11:4:z rel:12:4:z rel:13:4:z rel:14:4:z joint:31:14 joint:32:14 joint:33:14 joint:34:14; do
  json="$("$mlce" estimate "$iso" --channel "$ch" --json --quiet 2>/dev/null)"
  printf '  %-12s lambda %+.4f 1/s over %s of 4001 samples: %s, %s\n' "$ch" "$(printf '%s' "$json" | field lambda)" \
    "$(printf '%s' "$json" | field n_points)" "$(printf '%s' "$json" | field stability)" "$(printf '%s' "$json" | field motion)"
done
