#!/usr/bin/env bash
# Parse throughput and peak memory of the MBDyn text reader on large .mov files made by repeating
# the blocks of a real sample (times continue from the .out of the sample).
#   bench/reader_throughput.sh [BUILD_DIR] [SAMPLE_PREFIX] [REPEATS...]
# Files are written to a temporary directory first, so the read comes from the page cache: this
# measures parsing, not the disk.
set -euo pipefail
build="${1:-build}"
sample="${2:-data/mbdyn/c3zero_242rpm_cyhalf_10s/c3zero_242rpm_cyhalf}"
shift 2 2>/dev/null || shift $#
repeats=("${@:-10 50}")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "| .mov size | blocks | channel | seconds | MB/s | peak RSS |"
echo "|---|---|---|---|---|---|"
# MB/s is of the text scanned (.mov and .out); for the set gzipped file by file (PREFIX.ext.gz,
# gzip's default level) the same text bytes over its seconds, so the rows compare.
read_row() {  # read_row PREFIX SPEC TEXT_BYTES LABEL
  local line secs rss
  line=$( { /usr/bin/time -f "RSS %M" "$build/read_channel" "$1" "$2"; } 2>&1 )
  secs=$(sed -nE 's/.*seconds ([0-9.]+).*/\1/p' <<<"$line")
  rss=$(sed -nE 's/.*RSS ([0-9]+).*/\1/p' <<<"$line")
  echo "| $4 | $blocks | $2 | $secs | $(awk -v b="$3" -v s="$secs" 'BEGIN { printf "%.0f", b / s / 1e6 }') | $(( rss / 1024 )) MB |"
}
for r in ${repeats[@]}; do
  p="$work/big$r"
  cp "$sample.log" "$p.log"
  : > "$p.mov"
  for ((k = 0; k < r; k++)); do cat "$sample.mov" >> "$p.mov"; done
  blocks=$(( $(wc -l < "$p.mov") / 7 ))
  awk -v n="$blocks" 'BEGIN { print "# Step Time TStep NIter ResErr SolErr SolConv Out";
       for (k = 0; k < n; k++) printf "Step %d %.17g 0.005 2 1e-08 0 0 1\n", k, 0.005 * k }' > "$p.out"
  text=$(( $(stat -c %s "$p.mov") + $(stat -c %s "$p.out") ))  # what is scanned: the .mov and the .out
  for spec in node:13:x rel:13:4:z; do read_row "$p" "$spec" "$text" "$(( $(stat -c %s "$p.mov") / 1000000 )) MB"; done
  gzip -k -n "$p.mov" "$p.out" && mv "$p.mov" "$p.plain.mov" && mv "$p.out" "$p.plain.out"
  for spec in node:13:x rel:13:4:z; do
    read_row "$p" "$spec" "$text" "$(( $(stat -c %s "$p.mov.gz") / 1000000 )) MB gzip"
  done
  rm -f "$p".*
done
# The repeated blocks compress better than a run does: the sample's own ratio, for scale.
echo
echo "sample $sample.mov: $(stat -c %s "$sample.mov") bytes, $(gzip -c -n "$sample.mov" | wc -c) gzipped"

# Column files (as `mlce extract` or a spreadsheet writes them): a time column and three channels
# at 17 significant digits, read for one channel. The reader streams the lines; memory is the
# selected column and each row's line number (kept to name a bad value's line).
echo
echo "| column file size | rows | channel | seconds | MB/s | peak RSS |"
echo "|---|---|---|---|---|---|"
for rows in 1000000 5000000; do
  f="$work/series$rows.csv"
  awk -v n="$rows" 'BEGIN { print "time,x,y,z";
       for (k = 0; k < n; k++) { t = 0.01 * k; printf "%.17g,%.17g,%.17g,%.17g\n", t, sin(t), cos(1.3 * t), sin(0.7 * t) * cos(t) } }' > "$f"
  line=$( { /usr/bin/time -f "RSS %M" "$build/read_channel" "$f" col:2; } 2>&1 )
  secs=$(sed -nE 's/.*seconds ([0-9.]+).*/\1/p' <<<"$line")
  mbs=$(sed -nE 's/.*throughput ([0-9]+) MB.*/\1/p' <<<"$line")
  rss=$(sed -nE 's/.*RSS ([0-9]+).*/\1/p' <<<"$line")
  echo "| $(( $(stat -c %s "$f") / 1000000 )) MB | $rows | col:2 | $secs | $mbs | $(( rss / 1024 )) MB |"
  rm -f "$f"
done
