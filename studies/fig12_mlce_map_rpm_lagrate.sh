#!/usr/bin/env bash
# Paper 001 Fig. 12: MLCE (Rosenstein, blade 3 lag) over rotor speed x initial lag rate of blade 3,
# blade 3 inoperative (c_y = 25539.35): a colour map; the MLCE ~ 0 region is where the motion ends on
# the limit cycle, negative where it decays back to rest.
#   studies/fig12_mlce_map_rpm_lagrate.sh [BUILD_DIR] [OUT_DIR] -> fig12.csv, fig12.png
set -euo pipefail
build="${1:-build}"; out="${2:-studies/out}"; mkdir -p "$out"
"$build/mlce" sweep scenes/c3zero_242rpm.scene --x0 0 --param rpm=180:340:10 --param init:zetadot3=0.5:3:0.5 \
  --method rosenstein --out "$out/fig12.csv" --plot "$out/fig12.png"
