#!/usr/bin/env bash
# What an analyst reads from windows of Hammond's runs: the ad-hoc model of each bundled scene over
# 120 s (`mlce simulate --format columns`), blade 3's lag, the airframe's x and y, and blade 1's
# lag, each estimated over 14 windows [from, to] (s) as `mlce estimate --from --to` cuts them; per
# window lambda (1/s), the reading's stability and motion; then how often each motion was read.
# None of these motions is chaotic (decays, growths into a limit cycle, limit cycles), so a
# "chaotic" reading is a wrong one.
#   bench/hammond_windows.sh [BUILD_DIR]        (about 70 s)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
mlce="$build/mlce"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2- | tr -d '"'; }  # the key's first value (each is unique)
for scene in isotropic_200rpm c3zero_124rpm c3zero_242rpm nonlinear_CL0 nonlinear_CLnominal; do
  "$mlce" simulate "$here/scenes/$scene.scene" --t_end 120 --format columns --out "$work/$scene" --quiet 2>/dev/null
  for column in 4:zeta3 6:x_h 7:y_h 2:zeta1; do
    for window in 0:10 0:20 0:30 0:60 0:120 5:20 5:30 10:30 10:60 20:40 30:60 60:120 2:12 15:25; do
      json="$("$mlce" estimate "$work/$scene.txt" --time-column 1 --column "${column%%:*}" --from "${window%%:*}" \
              --to "${window##*:}" --json --quiet 2>/dev/null || true)"
      if [ -z "$json" ]; then
        printf '%-20s %-6s %-7s  refused\n' "$scene" "${column##*:}" "${window%%:*}..${window##*:}"
        continue
      fi
      printf '%-20s %-6s %-7s  lambda %+10.4f  %-12s %s\n' "$scene" "${column##*:}" "${window%%:*}..${window##*:}" \
        "$(printf '%s' "$json" | field lambda)" "$(printf '%s' "$json" | field stability)" \
        "$(printf '%s' "$json" | field motion)"
    done
  done
done > "$work/table.txt"
cat "$work/table.txt"
echo "readings over $(wc -l < "$work/table.txt") windows:"
awk '$4 == "refused" { n["refused"]++; next } { $1 = $2 = $3 = $4 = $5 = ""; sub(/^ +/, ""); n[$0]++ }
     END { for (k in n) printf "  %4d  %s\n", n[k], k }' \
  "$work/table.txt" | sort -rn
