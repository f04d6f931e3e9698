#!/usr/bin/env bash
# Line coverage of the libraries and the CLI by the test suite (gcc --coverage, gcov):
#   scripts/coverage.sh [BUILD_DIR]   (default build-coverage beside ./run's build; ~15 min on 2 cores)
# Builds the project with --coverage (RelWithDebInfo, no benchmarks), runs ctest, and prints each
# source file of mlce/ reader/ models/ spectrum/ ode/ apps/ with its executed and executable lines,
# least covered first, then the total. package_consumer is left out: it builds a separate project
# against the installed package, whose link does not carry gcov's runtime.
# gcov counts a statement written over several lines on one of them, so a line listed as not run
# may be an argument line of a call that ran; the file figures are gcov's own.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cov="${1:-$here/build-coverage}"
jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$here" -B "$cov" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS=--coverage \
  -DCMAKE_EXE_LINKER_FLAGS=--coverage -DMLCE_BUILD_BENCH=OFF >/dev/null
cmake --build "$cov" -j "$jobs"
find "$cov" -name '*.gcda' -delete
(cd "$cov" && ctest --output-on-failure -j "$jobs" -E '^package_consumer$')
echo "== line coverage by the tests (gcov): executed / executable lines" >&2
find "$cov/CMakeFiles" -name '*.gcda' | while read -r gcda; do
  # Each object's own source only (its headers are counted with the files that define them).
  (cd "$(dirname "$gcda")" && gcov -n -o . "$(basename "$gcda")" 2>/dev/null) |
    awk -v root="$here/" '
      /^File / { file = substr($2, 2, length($2) - 2); next }
      /^Lines executed:/ && file != "" {
        split($2, p, ":"); pct = p[2] + 0; n = $4 + 0
        if (index(file, root) == 1 && file ~ /\/(mlce|reader|models|spectrum|ode|apps)\/.*\.cpp$/)
          printf "%s %d %d\n", substr(file, length(root) + 1), int(pct * n / 100 + 0.5), n
        file = "" }'
done | sort -u | awk '
  { file[NR] = $1; run[NR] = $2; all[NR] = $3; total_run += $2; total += $3 }
  END {
    for (i = 1; i <= NR; ++i) printf "%6.1f %%  %5d / %5d  %s\n", 100 * run[i] / all[i], run[i], all[i], file[i] | "sort -n"
    close("sort -n")
    printf "%6.1f %%  %5d / %5d  all %d files\n", 100 * total_run / total, total_run, total, NR }'
