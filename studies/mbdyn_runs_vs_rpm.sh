#!/usr/bin/env bash
# Paper 001 §5 reads the MLCE of MBDyn runs over the rotor speed. Here the runs are written by the
# ad-hoc model in MBDyn's text format (`mlce simulate --format mbdyn`: .log, .out, .mov, read by the
# same reader as a real MBDyn set), blade 3's damper inoperative, x_h(0) = 0.1 m, 20 s each (T_END), at
# 180..340 rpm; `mlce estimate RUN1 RUN2 ... --param rpm=...` reads blade 3's lag (rel:13:4:z) of
# every run in one table, beside the largest Floquet exponent of the same model (`mlce sweep
# --method floquet`), an independent computation from the linearisation: unstable from 210.37 to
# 307.08 rpm (README "Blade 3 inoperative: the unstable band").
#   studies/mbdyn_runs_vs_rpm.sh [BUILD_DIR] [OUT_DIR] [T_END] -> runs_vs_rpm_{mlce,floquet}.csv, runs_vs_rpm.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; t_end="${3:-20}"; mkdir -p "$out"
scene=scenes/c3zero_242rpm.scene
runs=()
for rpm in 180 200 220 240 260 280 300 320 340; do
  mkdir -p "$out/runs/rpm$rpm"
  "$build/mlce" simulate $scene --rpm $rpm --t_end "$t_end" --out "$out/runs/rpm$rpm/hammond" --format mbdyn --quiet
  runs+=("$out/runs/rpm$rpm/hammond.mov")
done
"$build/mlce" estimate "${runs[@]}" --channel rel:13:4:z --param rpm=180:340:20 --csv "$out/runs_vs_rpm_mlce.csv" --quiet
"$build/mlce" sweep $scene --param rpm=180:340:20 --method floquet --out "$out/runs_vs_rpm_floquet.csv" --quiet
gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced
set output '$out/runs_vs_rpm.png'
set datafile separator ','
set grid
set key below
set xzeroaxis lt -1 lc 'gray40'
set xlabel 'rotor speed (rpm)'
set ylabel 'largest exponent (1/s)'
set title 'blade 3 damper inoperative: MLCE of runs in MBDyn format and the largest Floquet exponent'
set offsets graph 0.03, graph 0.03, 0, 0
plot '$out/runs_vs_rpm_mlce.csv' every ::1 using 3:4:5:6 with yerrorbars pt 7 lw 2 title 'MLCE (Rosenstein) and its 95 % interval', \
     '$out/runs_vs_rpm_floquet.csv' every ::1 using 1:2 with linespoints pt 5 lw 1 title 'largest Floquet exponent'
GP
echo "wrote $out/runs_vs_rpm_mlce.csv, $out/runs_vs_rpm_floquet.csv and $out/runs_vs_rpm.png"
