#!/usr/bin/env bash
# What the estimator reads on damped linear oscillators, whose truth is known exactly: lambda = -zeta
# omega, and the motion decays (stable). 560 series of `make_series oscillator N DT ZETA OMEGA`
# (zeta 0.005-0.4, omega 1-20 rad/s, dt 0.002-0.03 s, N 1000-10^4, from 0.2 to 950 periods), each
# estimated with every parameter automatic; per series the periods and e-folds it spans, lambda, its
# relative error, the reading's stability and motion and R^2 ("refused" where the series is too short
# to estimate); then how often each reading was given. "unstable" is a wrong reading on every one.
#   bench/oscillator_readings.sh [BUILD_DIR]        (about 2 min)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2- | tr -d '"'; }  # the key's first value (each is unique)
for zeta in 0.005 0.01 0.02 0.05 0.1 0.2 0.4; do
  for omega in 1 3.14159265358979 6.28318530717959 20; do
    for dt in 0.002 0.005 0.01 0.03; do
      for n in 1000 1500 2000 3000 10000; do
        "$build/make_series" oscillator "$n" "$dt" "$zeta" "$omega" > "$work/s.txt"
        span="$(awk -v n="$n" -v dt="$dt" -v z="$zeta" -v w="$omega" \
                'BEGIN { printf "%7.1f periods %7.1f e-folds", n * dt * w / 6.283185307179586, z * w * n * dt }')"
        json="$("$build/mlce" estimate "$work/s.txt" --time-column 1 --column 2 --json --quiet 2>/dev/null || true)"
        if [ -z "$json" ]; then
          printf 'zeta %-5s omega %-6.3g dt %-5s N %-5s %s  refused\n' "$zeta" "$omega" "$dt" "$n" "$span"
          continue
        fi
        lambda="$(printf '%s' "$json" | field lambda)"
        printf 'zeta %-5s omega %-6.3g dt %-5s N %-5s %s  lambda %+9.4f  error %+9.1f %%  R^2 %-6s  %s %s\n' \
          "$zeta" "$omega" "$dt" "$n" "$span" "$lambda" \
          "$(awk -v l="$lambda" -v z="$zeta" -v w="$omega" 'BEGIN { t = -z * w; printf "%.1f", 100 * (l - t) / -t }')" \
          "$(printf '%s' "$json" | field r2 | cut -c1-6)" \
          "$(printf '%s' "$json" | field stability)" "$(printf '%s' "$json" | field motion)"
      done
    done
  done
done > "$work/table.txt"
cat "$work/table.txt"
echo "readings over $(wc -l < "$work/table.txt") series:"
awk '/ refused$/ { n["refused"]++; next } { sub(/.*R\^2 [^ ]+ +/, ""); n[$0]++ }
     END { for (k in n) printf "  %4d  %s\n", n[k], k }' "$work/table.txt" | sort -rn
