#!/usr/bin/env bash
# Paper 001 Figs. 4-5: blade 3 inoperative (c_3 = 0, c_y = 25539.35 per the data README), largest
# exponent versus rotor speed by Floquet (about x = 0), discrete QR (along the motion) and the
# MLCE by Rosenstein on blade 3's lag: Floquet is positive in the unstable band (~210-307 rpm)
# while QR and the MLCE are ~0 there (the motion settles on a limit cycle).
#   studies/fig4_5_blade3_floquet_qr_mlce.sh [BUILD_DIR] [OUT_DIR] -> fig4_5.csv, fig4_5.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; mkdir -p "$out"
scene=scenes/c3zero_242rpm.scene
"$build/mlce" sweep $scene --param rpm=150:350:5 --method floquet --out "$out/fig4_5_floquet.csv"
"$build/mlce" sweep $scene --param rpm=150:350:5 --method rosenstein --out "$out/fig4_5_mlce.csv"
"$build/mlce" sweep $scene --param rpm=150:350:10 --method qr --preset fast --out "$out/fig4_5_qr.csv"
# rpm, Floquet lambda_1, MLCE, QR lambda_1 (QR every other rpm: blank elsewhere)
rows() { grep -v '^#' "$1" | tail -n +2 | cut -d, -f1,2; }
awk -F, 'FNR == 1 { file++ } file == 1 { f[$1] = $2; order[++n] = $1 } file == 2 { m[$1] = $2 } file == 3 { q[$1] = $2 }
         END { print "rpm,floquet_lambda1,mlce_rosenstein,qr_lambda1"
               for (i = 1; i <= n; ++i) { k = order[i]; print k "," f[k] "," m[k] "," (k in q ? q[k] : "") } }' \
  <(rows "$out/fig4_5_floquet.csv") <(rows "$out/fig4_5_mlce.csv") <(rows "$out/fig4_5_qr.csv") > "$out/fig4_5.csv"
gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced
set output '$out/fig4_5.png'
set datafile separator ','
set key top right autotitle columnhead
set grid
set xlabel 'rotor speed (rpm)'
set ylabel 'largest exponent (1/s)'
set title 'blade 3 inoperative: Floquet (x = 0) vs QR and Rosenstein (along the motion)'
plot '$out/fig4_5.csv' using 1:2 with lines lw 2, '' using 1:3 with linespoints lw 2 pt 7 ps 0.6, '' using 1:(strlen(strcol(4)) == 0 ? 1/0 : \$4) with points pt 5 ps 1
GP
echo "wrote $out/fig4_5.csv and $out/fig4_5.png"
