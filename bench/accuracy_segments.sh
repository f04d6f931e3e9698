#!/usr/bin/env bash
# Spread of the automatic estimate over independent stretches of one long run: each system is
# generated for 4 x 10^4 samples and cut into four series of 10^4, each estimated on its own.
#   bench/accuracy_segments.sh [BUILD_DIR]
set -euo pipefail
build="${1:-build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "| system | known | segment 1 | segment 2 | segment 3 | segment 4 |"
echo "|---|---|---|---|---|---|"
# Each spec: system, make_series' third argument (the step dt; for the logistic map its r, since
# make_series logistic N R: a 1 there made r = 1, a series that dies out), the known exponent.
for spec in "lorenz 0.01 0.9056" "roessler 0.1 0.0714" "henon 1 0.4192" "logistic 4 0.6931"; do
  set -- $spec
  "$build/make_series" "$1" 40000 "$2" > "$work/all.txt"
  row="| $1 | $3 |"
  for k in 0 1 2 3; do
    awk -v k=$k '!/^#/ { if (n >= k*10000 && n < (k+1)*10000) print; n++ }' "$work/all.txt" > "$work/seg.txt"
    l=$("$build/mlce" estimate "$work/seg.txt" --time-column 1 --column 2 --json --quiet |
        sed -E 's/.*"lambda":([-0-9.eE+]+).*/\1/')
    row="$row $(printf '%.4g' "$l") |"
  done
  echo "$row"
done
