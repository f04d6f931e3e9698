#!/usr/bin/env bash
# What the estimator reads on linear oscillators, whose truth is known exactly: lambda = -zeta omega.
# Damped (the default): 560 series of `make_series oscillator N DT ZETA OMEGA` (zeta 0.005-0.4, omega
# 1-20 rad/s, dt 0.002-0.03 s, N 1000-10^4, from 0.2 to 950 periods); the motion decays (stable), and
# "unstable" is a wrong reading on every one. `growths`: 180 series with zeta -0.005 ... -0.1 (omega 1,
# pi, 2 pi; dt 0.002-0.03 s; N 1000-10^4); the motion grows (unstable, a growing oscillation), and
# "stable" is a wrong reading on every one. Each estimated with every parameter automatic; per series
# the periods and e-folds it spans, lambda, its relative error, R^2 and the reading's stability and
# motion ("refused" where the series is too short to estimate); then how often each reading was given.
# `tones`: 40 series of two tones of unrelated frequencies, sin t + A sin(R t + 0.3) (R = sqrt 2, the
# golden ratio, sqrt 5, 1/sqrt 2; A = 0.2, 0.5; dt = 0.01 s; N = 1500-10^4, 2.4-16 periods of the
# first tone): a torus, largest exponent 0 (neutral), where "unstable" is a wrong reading; per series
# lambda, how closely the record repeats itself one period on, scaled (`short_run_repeat`: one mode
# repeats to ~0), and the reading.
#   bench/oscillator_readings.sh [BUILD_DIR] [growths|tones]        (about 2 min; growths 1 min; tones 15 s)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
if [ "${2:-}" = growths ]; then
  zetas="-0.005 -0.01 -0.02 -0.05 -0.1"; omegas="1 3.14159265358979 6.28318530717959"; steps="0.002 0.01 0.03"
  lengths="1000 2000 3000 10000"
else
  zetas="0.005 0.01 0.02 0.05 0.1 0.2 0.4"; omegas="1 3.14159265358979 6.28318530717959 20"
  steps="0.002 0.005 0.01 0.03"; lengths="1000 1500 2000 3000 10000"
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2- | tr -d '"'; }  # the key's first value (each is unique)
count_readings() {
  echo "readings over $(wc -l < "$1") series:"
  awk '/ refused$/ { n["refused"]++; next } { sub(/.*R\^2 [^ ]+ +/, ""); sub(/.*repeat [^ ]+ +/, ""); n[$0]++ }
       END { for (k in n) printf "  %4d  %s\n", n[k], k }' "$1" | sort -rn
}
if [ "${2:-}" = tones ]; then
  for ratio in 1.4142135623731 1.61803398874989 2.23606797749979 0.707106781186548; do
    for amp in 0.2 0.5; do
      for n in 1500 2000 3000 4000 10000; do
        awk -v n="$n" -v r="$ratio" -v a="$amp" \
            'BEGIN { for (i = 0; i < n; i++) { t = 0.01 * i; printf "%.2f %.15g\n", t, sin(t) + a * sin(r * t + 0.3) } }' > "$work/s.txt"
        span="$(awk -v n="$n" 'BEGIN { printf "%5.1f periods", n * 0.01 / 6.283185307179586 }')"
        json="$("$build/mlce" estimate "$work/s.txt" --time-column 1 --column 2 --json --quiet 2>/dev/null || true)"
        if [ -z "$json" ]; then
          printf 'R %-6.4g A %-3s N %-5s %s  refused\n' "$ratio" "$amp" "$n" "$span"
          continue
        fi
        repeat="$(printf '%s' "$json" | grep -o '"short_run_repeat":{[^}]*}' | field difference || true)"  # absent before 2026-12
        printf 'R %-6.4g A %-3s N %-5s %s  lambda %+8.4f  repeat %-6.4s  %s %s\n' "$ratio" "$amp" "$n" "$span" \
          "$(printf '%s' "$json" | field lambda)" "${repeat:-null}" \
          "$(printf '%s' "$json" | field stability)" "$(printf '%s' "$json" | field motion)"
      done
    done
  done > "$work/table.txt"
  cat "$work/table.txt"
  count_readings "$work/table.txt"
  exit 0
fi
for zeta in $zetas; do
  for omega in $omegas; do
    for dt in $steps; do
      for n in $lengths; do
        "$build/make_series" oscillator "$n" "$dt" "$zeta" "$omega" > "$work/s.txt"
        span="$(awk -v n="$n" -v dt="$dt" -v z="$zeta" -v w="$omega" \
                'BEGIN { e = z * w * n * dt; printf "%7.1f periods %7.1f e-folds", n * dt * w / 6.283185307179586, e < 0 ? -e : e }')"
        json="$("$build/mlce" estimate "$work/s.txt" --time-column 1 --column 2 --json --quiet 2>/dev/null || true)"
        if [ -z "$json" ]; then
          printf 'zeta %-5s omega %-6.3g dt %-5s N %-5s %s  refused\n' "$zeta" "$omega" "$dt" "$n" "$span"
          continue
        fi
        lambda="$(printf '%s' "$json" | field lambda)"
        printf 'zeta %-5s omega %-6.3g dt %-5s N %-5s %s  lambda %+9.4f  error %+9.1f %%  R^2 %-6s  %s %s\n' \
          "$zeta" "$omega" "$dt" "$n" "$span" "$lambda" \
          "$(awk -v l="$lambda" -v z="$zeta" -v w="$omega" 'BEGIN { t = -z * w; printf "%.1f", 100 * (l - t) / (t < 0 ? -t : t) }')" \
          "$(printf '%s' "$json" | field r2 | cut -c1-6)" \
          "$(printf '%s' "$json" | field stability)" "$(printf '%s' "$json" | field motion)"
      done
    done
  done
done > "$work/table.txt"
cat "$work/table.txt"
count_readings "$work/table.txt"
