#!/usr/bin/env bash
# Paper 001 Fig. 9: amplitude of blade 3's lag (half its settled peak-to-peak range) versus rotor
# speed: ~0 below the band, a jump to a large limit cycle near 210 rpm.
#   studies/fig9_blade3_amplitude_vs_rpm.sh [BUILD_DIR] [OUT_DIR] -> fig9.csv, fig9.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; mkdir -p "$out"
"$build/mlce" sweep scenes/c3zero_242rpm.scene --param rpm=150:350:2 --method rosenstein --out "$out/fig9_sweep.csv"
awk -F, '!/^#/ { if (h++ == 0) print "rpm,blade3_lag_amplitude_rad"; else print $1 "," $7 }' "$out/fig9_sweep.csv" > "$out/fig9.csv"
gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced
set output '$out/fig9.png'
set datafile separator ','
set grid
set key off
set xlabel 'rotor speed (rpm)'
set ylabel 'blade 3 lag amplitude (rad)'
set title 'blade 3 inoperative: settled lag amplitude'
plot '$out/fig9.csv' every ::1 using 1:2 with linespoints lw 2 pt 7 ps 0.6
GP
echo "wrote $out/fig9.csv and $out/fig9.png"
