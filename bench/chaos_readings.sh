#!/usr/bin/env bash
# What the reading says on chaotic flows of various lengths, every parameter automatic: consecutive
# segments (`mlce estimate --from --to`) of one long Lorenz x series (dt 0.01 s; 2000, 3000, 5000 and
# 10^4 samples, 40 segments each) and one long Roessler x series (dt 0.1 s; 3000, 5000 and 10^4
# samples), the segments already on the attractor. Every segment is chaotic: "unstable, chaotic" is
# the right reading; "undetermined" is an honest miss (the summary says why); anything else is a
# wrong reading. Per length: how often each reading was given, the range of the envelope line's t, then each miss with lambda, its fit region (curve steps), the
# amplitude's envelope rate (1/s) and its t (rate over its standard error), the ratio of the last
# third's RMS to the first's, and the summary's first words (t 0: no envelope line on so short a run).
#   bench/chaos_readings.sh [BUILD_DIR]        (about 2 min)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

field() { grep -o "\"$1\":[^,}]*" | head -n 1 | cut -d: -f2- | tr -d '"'; }  # the key's first value
"$build/make_series" lorenz 400000 0.01 > "$work/lorenz.txt"
"$build/make_series" roessler 400000 0.1 > "$work/roessler.txt"
for run in lorenz:0.01:2000 lorenz:0.01:3000 lorenz:0.01:5000 lorenz:0.01:10000 \
           roessler:0.1:3000 roessler:0.1:5000 roessler:0.1:10000; do
  IFS=: read -r flow dt length <<< "$run"
  : > "$work/table.txt"
  for segment in $(seq 0 39); do
    read -r from to < <(awk -v s="$segment" -v n="$length" -v dt="$dt" \
                          'BEGIN { printf "%.4f %.4f\n", s * n * dt, ((s + 1) * n - 0.5) * dt }')
    json="$("$build/mlce" estimate "$work/$flow.txt" --time-column 1 --column 2 --from "$from" --to "$to" --json \
            --quiet 2>/dev/null || true)"
    if [ -z "$json" ]; then
      echo "refused from $from" >> "$work/table.txt"
      continue
    fi
    printf '%s %s from %-8s lambda %+8.4f  fit %-10s envelope %s 1/s (t %+6.2f)  ratio %-5.5s  %s\n' \
      "$(printf '%s' "$json" | field stability)" "$(printf '%s' "$json" | field motion)" "$from" \
      "$(printf '%s' "$json" | field lambda)" "$(printf '%s' "$json" | grep -o '"fit":\[[0-9]*,[0-9]*\]' | cut -d: -f2)" \
      "$(printf '%s' "$json" | field envelope_rate | awk '{ print $1 == "null" ? "null" : sprintf("%+.2e", $1) }')" \
      "$(awk -v e="$(printf '%s' "$json" | field envelope_rate)" -v s="$(printf '%s' "$json" | field envelope_rate_stderr)" \
             'BEGIN { print (s + 0 > 0 ? e / s : 0) }')" \
      "$(printf '%s' "$json" | field amplitude_ratio)" \
      "$(printf '%s' "$json" | field summary | cut -c1-140)" >> "$work/table.txt"
  done
  echo "== $flow x, dt $dt, $length samples: 40 segments"
  awk '{ print "  " $1 " " $2 }' "$work/table.txt" | sort | uniq -c | sort -rn
  # The envelope line's t over every segment: how far a chaotic amplitude's wander tilts it by chance
  # (the reading counts a fall against lambda > 0 from t <= -4: mlce/src/reading.cpp, kSignificantFall).
  awk '{ for (i = 1; i < NF; ++i) if ($i == "(t") { t = $(i + 1) + 0; if (n++ == 0 || t < lo) lo = t; if (n == 1 || t > hi) hi = t } }
       END { printf "  envelope t over the segments: %+.2f .. %+.2f\n", lo, hi }' "$work/table.txt"
  grep -v '^unstable chaotic' "$work/table.txt" | sed 's/^/    miss: /' || true
done
