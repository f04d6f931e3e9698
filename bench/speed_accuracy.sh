#!/usr/bin/env bash
# Speed/accuracy trade of the MLCE on the blade-3-inoperative rotor (paper 001 Figs. 4-5): the
# error of `mlce simulate` + `mlce estimate` (blade 3 lag, --from auto) against the independent
# reference at each rotor speed -- the Floquet exponent below the band (170, 185, 200 rpm), where the
# motion decays, and 0 inside it (235, 250, 265 rpm), where it settles on a limit cycle -- versus
# wall time (simulate + estimate, summed over the six speeds). One knob changes per row, from the
# baseline (run 90 s, output step 5 ms, rtol 1e-8, 5000 references, m/delay/horizon
# automatic, exact neighbours); the first three rows are the presets of `mlce sweep`.
#   bench/speed_accuracy.sh [BUILD_DIR] [OUT_DIR]  -> table on stdout, OUT_DIR/speed_accuracy.{csv,png}
set -euo pipefail
build="${1:-build}"; out="${2:-bench/out}"; mkdir -p "$out"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
scene=scenes/c3zero_242rpm.scene
speeds="170 185 200 235 250 265"
declare -A ref
for r in $speeds; do
  if [ "$r" -lt 210 ]; then
    ref[$r]=$("$build/mlce" floquet $scene --rpm $r --json | sed -E 's/.*"exponents":\[([-0-9.eE+]+),.*/\1/')
  else
    ref[$r]=0
  fi
done
now() { date +%s.%N; }
# run NAME T_END DT_OUT RTOL ESTIMATE_ARGS...
run() {
  local name="$1" t_end="$2" dt="$3" rtol="$4"; shift 4
  : > "$work/point.txt"
  for r in $speeds; do
    local t0 t1 l
    t0=$(now)
    "$build/mlce" simulate $scene --rpm $r --t_end $t_end --dt_out $dt --rtol $rtol --out "$work/run" --quiet
    l=$("$build/mlce" estimate "$work/run" --channel rel:13:4:z --from auto --quiet --json "$@" |
        sed -E 's/.*"lambda":([-0-9.eE+]+).*/\1/')
    t1=$(now)
    echo "$t0 $t1 $l ${ref[$r]}" >> "$work/point.txt"
  done
  awk -v name="$name" '{ t += $2 - $1; e = $3 - $4; if (e < 0) e = -e; s += e; if (e > m) m = e }
       END { printf "%s,%.3f,%.5f,%.5f\n", name, t, s / NR, m }' "$work/point.txt" | tee -a "$work/rows.csv" >&2
}
: > "$work/rows.csv"
echo "reference: $(for r in $speeds; do printf '%s rpm %.5f; ' $r ${ref[$r]}; done)" >&2
run "preset fast: 60 s; 20 ms; rtol 1e-6; 2000 refs" 60 0.02 1e-6 --refs 2000
run "preset balanced: 90 s; 20 ms; rtol 1e-8; 5000 refs" 90 0.02 1e-8 --refs 5000
run "preset accurate: 180 s; 10 ms; rtol 1e-10; 20000 refs" 180 0.01 1e-10 --refs 20000
run "baseline: 90 s; 5 ms; rtol 1e-8; 5000 refs" 90 0.005 1e-8 --refs 5000
run "run 30 s" 30 0.005 1e-8 --refs 5000
run "run 60 s" 60 0.005 1e-8 --refs 5000
run "output step 10 ms" 90 0.01 1e-8 --refs 5000
run "output step 20 ms" 90 0.02 1e-8 --refs 5000
run "rtol 1e-6" 90 0.005 1e-6 --refs 5000
run "rtol 1e-10" 90 0.005 1e-10 --refs 5000
run "dim 2" 90 0.005 1e-8 --refs 5000 --dim 2
run "dim 5" 90 0.005 1e-8 --refs 5000 --dim 5
run "delay 10" 90 0.005 1e-8 --refs 5000 --delay 10
run "delay 80" 90 0.005 1e-8 --refs 5000 --delay 80
run "horizon 400" 90 0.005 1e-8 --refs 5000 --horizon 400
run "1000 references" 90 0.005 1e-8 --refs 1000
run "all references" 90 0.005 1e-8 --refs all
run "approximate neighbours eps 1" 90 0.005 1e-8 --refs 5000 --eps 1
run "run 180 s; output step 20 ms" 180 0.02 1e-8 --refs 5000
{ echo "setting,seconds,mean_abs_error,max_abs_error"; cat "$work/rows.csv"; } > "$out/speed_accuracy.csv"
echo "| setting | wall s (6 speeds) | mean \|error\| (1/s) | max \|error\| (1/s) |"
echo "|---|---|---|---|"
awk -F, 'NR > 1 { printf "| %s | %s | %s | %s |\n", $1, $2, $3, $4 }' "$out/speed_accuracy.csv"
gnuplot <<GP
set terminal pngcairo size 1000,650 noenhanced
set output '$out/speed_accuracy.png'
set datafile separator ','
set logscale y
set grid
set key off
set xlabel 'wall time, simulate + estimate over 6 rotor speeds (s)'
set ylabel 'mean |MLCE - reference| (1/s)'
set title 'MLCE speed/accuracy, blade 3 inoperative (reference: Floquet below the band, 0 on the limit cycle)'
plot '$out/speed_accuracy.csv' every ::1 using 2:3 with points pt 7 ps 1.5, '' every ::1 using 2:3:1 with labels offset 1,0.6 left font ',8'
GP
echo "wrote $out/speed_accuracy.csv and $out/speed_accuracy.png" >&2
