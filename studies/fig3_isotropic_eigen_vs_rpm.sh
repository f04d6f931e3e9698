#!/usr/bin/env bash
# Paper 001 Fig. 3: exponents of the isotropic rotor (printed c_y = 51078.7) versus rotor speed,
# from the multiblade eigenvalues; the -c/(2 I_b) = -1.875 1/s pair is flat over the whole range.
#   studies/fig3_isotropic_eigen_vs_rpm.sh [BUILD_DIR] [OUT_DIR]  -> OUT_DIR/fig3.csv, fig3.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; mkdir -p "$out"
"$build/mlce" sweep scenes/isotropic_200rpm.scene --param rpm=20:400:5 --method eigen \
  --out "$out/fig3.csv" --plot "$out/fig3.png"
