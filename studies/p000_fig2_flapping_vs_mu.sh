#!/usr/bin/env bash
# Paper 000 Fig. 2: flapping blade in forward flight, exponents and their sensitivity to the advance
# ratio mu versus mu, by Floquet (monodromy, analytic sensitivities) and by the discrete QR method
# with its sensitivities (paper 000 eqs. 12-28).
#   studies/p000_fig2_flapping_vs_mu.sh [BUILD_DIR] [OUT_DIR] -> p000_fig2_*.csv, p000_fig2.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; mkdir -p "$out"
scene=scenes/flapping_mu015.scene
"$build/mlce" sweep $scene --param mu=0:2:0.05 --method floquet --sensitivity mu --out "$out/p000_fig2_floquet.csv"
"$build/mlce" sweep $scene --param mu=0:2:0.2 --method qr --sensitivity mu --out "$out/p000_fig2_qr.csv"
gnuplot <<GP
set terminal pngcairo size 1000,800 noenhanced
set output '$out/p000_fig2.png'
set datafile separator ','
set multiplot layout 2,1
set grid
set key top right
set xlabel 'advance ratio mu'
set ylabel 'lambda (1/rad of azimuth)'
set title 'flapping blade: exponents (Floquet lines, QR points)'
plot '$out/p000_fig2_floquet.csv' every ::1 using 1:2 with lines lw 2 title 'Floquet lambda_1', \
     '' every ::1 using 1:3 with lines lw 2 title 'Floquet lambda_2', \
     '$out/p000_fig2_qr.csv' every ::1 using 1:2 with points pt 7 title 'QR lambda_1', \
     '' every ::1 using 1:3 with points pt 5 title 'QR lambda_2'
set ylabel 'd lambda / d mu'
set title 'sensitivity to mu'
plot '$out/p000_fig2_floquet.csv' every ::1 using 1:4 with lines lw 2 title 'Floquet dlambda_1/dmu', \
     '' every ::1 using 1:5 with lines lw 2 title 'Floquet dlambda_2/dmu', \
     '$out/p000_fig2_qr.csv' every ::1 using 1:4 with points pt 7 title 'QR dlambda_1/dmu', \
     '' every ::1 using 1:5 with points pt 5 title 'QR dlambda_2/dmu'
unset multiplot
GP
echo "wrote $out/p000_fig2_floquet.csv, $out/p000_fig2_qr.csv and $out/p000_fig2.png"
