#!/usr/bin/env bash
# End-to-end cost of `mlce estimate` (every parameter automatic) on Lorenz x, dt = 0.01, for
# N = 1e4, 1e5, 1e6 (or the N given): wall time (best of 3) and peak resident memory, as a
# Markdown table.
#   bench/scaling.sh [BUILD_DIR] [N ...]
set -euo pipefail
build="${1:-build}"
shift $(( $# > 0 ? 1 : 0 ))
sizes=("${@:-10000 100000 1000000}")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "| N | wall time (s, best of 3) | peak RSS (MB) | lambda (1/s) |"
echo "|---|---|---|---|"
for n in ${sizes[@]}; do
  "$build/make_series" lorenz "$n" 0.01 > "$work/lorenz.txt"
  best=""
  for _ in 1 2 3; do
    /usr/bin/time -f "%e %M" -o "$work/time" "$build/mlce" estimate "$work/lorenz.txt" --time-column 1 --column 2 \
      --json --quiet > "$work/out.json"
    read -r secs kb < "$work/time"
    if [ -z "$best" ] || awk "BEGIN{exit !($secs < $best)}"; then best=$secs; rss=$kb; fi
  done
  lambda=$(sed -E 's/.*"lambda":([-0-9.eE+]+).*/\1/' "$work/out.json")
  echo "| $n | $best | $((rss / 1024)) | $lambda |"
done
