#!/usr/bin/env bash
# What the estimator reads on Gaussian random walks (x += N(0, 1) per sample, `make_series random_walk
# N 0.01 SEED`): integrated noise, no attractor, the exponent of its deterministic part x[t+1] = x[t]
# is 0, and any reading of stability is wrong. 20 seeds at each of N = 1000, 10^4 and 10^5, every
# parameter automatic; per series lambda, the reading and the reason the estimate gives it is
# unreliable ("refused" where the series is too short to estimate); then how often each reading and
# each reason was given.
#   bench/random_walk_readings.sh [BUILD_DIR]        (about 2 min)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2- | tr -d '"'; }  # the key's first value (each is unique)
for n in 1000 10000 100000; do
  for seed in $(seq 1 20); do
    "$build/make_series" random_walk "$n" 0.01 "$seed" > "$work/s.txt"
    json="$("$build/mlce" estimate "$work/s.txt" --time-column 1 --column 2 --json --quiet 2>/dev/null || true)"
    if [ -z "$json" ]; then
      printf 'N %-6s seed %-2s  refused\n' "$n" "$seed"
      continue
    fi
    printf 'N %-6s seed %-2s  lambda %+8.4f  %s %s  [%s]\n' "$n" "$seed" "$(printf '%s' "$json" | field lambda)" \
      "$(printf '%s' "$json" | field stability)" "$(printf '%s' "$json" | field motion)" \
      "$(printf '%s' "$json" | field unreliable)"
  done
done > "$work/table.txt"
cat "$work/table.txt"
echo "readings over $(wc -l < "$work/table.txt") series:"
sed -E 's/.*lambda +[-+0-9.e]+ +//; s/ +\[.*//' "$work/table.txt" | sort | uniq -c | sort -rn
echo "reasons given:"
sed -E 's/.*\[(.*)\]$/\1/; s/^$/(none)/' "$work/table.txt" | sort | uniq -c | sort -rn
