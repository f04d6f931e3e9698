#!/usr/bin/env bash
# Paper 001 Fig. 11 / paper 000 Fig. 4: nonlinear lead-lag dampers (paper 000 eq. 39) at 242.4 rpm,
# largest exponent versus the damper's linear slope C_L (all blades): ~0 (limit cycle) for C_L up
# to about a third of nominal, then progressively negative, about -1 1/s at nominal (4067.5).
# This figure needs Table 1's printed c_y = 51078.7: with it the QR exponent is ~0 up to C_L ~ 1600
# and -0.94 1/s at nominal, the paper's description; with the halved c_y that reproduces Figs. 8-9
# the limit cycle persists up to C_L ~ 2800 and lambda_1 is -0.32 1/s at nominal
# (build/mlce sweep scenes/nonlinear_CL0.scene --param CL=0:4000:400 --method qr --preset fast [--cy 51078.7]).
# The MLCE is estimated on the hub displacement x_h, which the initial x_h = 0.1 m excites; the
# blade lags barely move (1e-7 rad) and sink into the integrator's absolute-tolerance noise.
#   studies/fig11_mlce_vs_CL.sh [BUILD_DIR] [OUT_DIR] -> fig11_*.csv, fig11.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; mkdir -p "$out"
scene=scenes/nonlinear_CL0.scene
"$build/mlce" sweep $scene --cy 51078.7 --param CL=0:4000:200 --method rosenstein --channel x_h --out "$out/fig11_mlce.csv"
"$build/mlce" sweep $scene --cy 51078.7 --param CL=0:4000:400 --method qr --preset fast --out "$out/fig11_qr.csv"
gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced
set output '$out/fig11.png'
set datafile separator ','
set grid
set key top right
set xlabel 'C_L (N m s/rad)'
set ylabel 'largest exponent (1/s)'
set title 'nonlinear dampers, 242.4 rpm, c_y 51078.7: MLCE (Rosenstein on x_h) and QR lambda_1'
plot '$out/fig11_mlce.csv' every ::1 using 1:2 with linespoints lw 2 pt 7 title 'MLCE (Rosenstein)', \
     '$out/fig11_qr.csv' every ::1 using 1:2 with points pt 5 ps 1.2 title 'QR lambda_1'
GP
echo "wrote $out/fig11_mlce.csv, $out/fig11_qr.csv and $out/fig11.png"
