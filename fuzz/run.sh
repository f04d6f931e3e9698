#!/usr/bin/env bash
# Builds the libFuzzer targets (the parsers, the estimator) with clang (ASan + UBSan) and runs each
# for a bounded time on a seed corpus made from the bundled data.   fuzz/run.sh [SECONDS_PER_TARGET] [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
secs="${1:-20}"
build="${2:-$here/build-fuzz}"
CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMLCE_FUZZ=ON >/dev/null
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)"
corpus="$build/corpus"
rm -rf "$corpus" && mkdir -p "$corpus"/{mbdyn_log,mbdyn_out,mbdyn_blocks,mbdyn_eigenanalysis,column_file,channel_spec,netcdf,gzip,estimate}
iso="$here/data/mbdyn/iso_200rpm_1s/iso_200rpm"
cp "$iso.log" "$corpus/mbdyn_log/"
head -c 4000 "$iso.out" > "$corpus/mbdyn_out/seed.out"
# late times printed by default (%g, 6 digits): the path that rebuilds them from Step x TStep
printf 'Step 0 1000 0 1 0 0 0 1\nStep 1 1000 0.005 2 1e-08 0 0 1\nStep 2 1000.01 0.005 2 1e-08 0 0 0\nStep 3 1000.01 0.005 2 1e-08 0 0 1\n' \
  > "$corpus/mbdyn_out/late.out"
# eigenvalue tables as MBDyn's solver.cc prints them: a NaN row (Lambda = -1), a failed QZ, the older PI row
printf 'Step 0 0 0.001 0 0 0 0 1\nInfo: 0, success BALANC="N" ILO=1 IHI=3 ABNRM=-1 BBNRM=-1\nMode n.       Real          Imag             Damp %%     Freq Hz\n       1:          -2 -      44.6766 j      4.47214     -7.11049\n       2:        -nan -         -nan j          100            0\n       3:          -2 +      44.6766 j      4.47214      7.11049\nStep 1 0.001 0.001 2 1e-12 0 0 1\nInfo: 3, the QZ iteration failed\nMode n.       Real          Imag             Damp %%     Freq Hz\n       1:            0 -           PI j            0    PI\n       2:          -2 +     -44.6766 j      4.47214     -7.11049\n' \
  > "$corpus/mbdyn_out/eig.out"
head -n 30 "$iso.mov" > "$corpus/mbdyn_blocks/seed.mov"
head -n 30 "$iso.jnt" > "$corpus/mbdyn_blocks/seed.jnt"
# eigenanalysis .m files as MBDyn writes them: dense matrices, sparse triplets, alpha with eigenvectors
printf '%% time: 0\ndTime = 0;\n%% coefficient\ndCoef = 0.05;\n%% F/xPrime + dCoef * F/x\nAplus = [1 -0.05 ;\n250 3 ];\n%% F/xPrime - dCoef * F/x\nAminus = [1 0.05 ;\n-250 2 ];\n' \
  > "$corpus/mbdyn_eigenanalysis/dense.m"
printf 'dTime = 1;\ndCoef = 5e-4;\nAplus = [1 1 1;\n2 2 3;\n];\nAplus = spconvert(Aplus);\nAminus = [1 1 1;\n2 2 -3;\n];\nAminus = spconvert(Aminus);\n' \
  > "$corpus/mbdyn_eigenanalysis/sparse.m"
printf 'dTime = 2;\ndCoef = 0.5;\n%% alphar, alphai, beta\nalpha = [0.9 0.1 1;\n0.9 -0.1 1;\n-1 0 1;\n];\n%% right eigenvectors\nVR = [\n1+i*2 1-i*2 3 ;\n4 5 6 ];\n' \
  > "$corpus/mbdyn_eigenanalysis/alpha.m"
head -n 50 "$here/data/lorenz_x.txt" > "$corpus/column_file/seed.txt"
printf '"","t","x # m"\n"1",0,0.5\n"2",0.01,"-0.25"\n' > "$corpus/column_file/quoted.csv"  # R's write.csv
printf 'when,t,x,note\n2026-11-27 01:00:00,0,0.5,ok\n2026-11-27 01:00:01,1,*****,\n' > "$corpus/column_file/labelled.csv"
printf 'when\tt\tx\n27-Nov-2026 01:00:00\t0\t\t0.5\n"a b"\t 1 2\t3\n' > "$corpus/column_file/tab.tsv"
printf '\xef\xbb\xbf"t";x\r\n0,01;-2,5E-03;\r\n0,02; 1,0D+01;\r\n' > "$corpus/column_file/european.csv"  # a comma locale's spreadsheet
for s in node:2:x joint:33:14 rel:13:4:z ine:11:3 col:2 mod:12.3:2 frc:5@2:3 var:elem.beam.100.F_I:2; do printf '%s' "$s" > "$corpus/channel_spec/$s"; done
# gzip files as analysts archive runs: one member, two members (cat a.gz b.gz), a column file
head -n 30 "$iso.mov" | gzip -c -n > "$corpus/gzip/seed.mov.gz"
{ head -n 7 "$iso.mov" | gzip -c -n; sed -n 8,14p "$iso.mov" | gzip -c -n; } > "$corpus/gzip/members.mov.gz"
head -n 50 "$here/data/lorenz_x.txt" | gzip -c -n > "$corpus/gzip/seed.txt.gz"
# the NetCDF header and its first records (a file cut short: the reader's truncated-file path)
head -c 24000 "$iso.nc" > "$corpus/netcdf/seed.nc"
# MBDyn's eigenanalysis variables (DataManager::OutputEigPrepare ...): dense matrices (eig.0), sparse
# triplets along the record dimension, more of them than output records (eig.1), alpha (eig.2), one planned
# analysis never performed (eig.3: fill values)
cat > "$corpus/eig.cdl" <<'CDL'  # ncgen reads its input twice: a file, not a pipe
netcdf eig {
dimensions:
  time = UNLIMITED ; vec3 = 3 ; eigensolutions = 4 ; eig_iSize = 2 ; eig_2_iNVec_out = 3 ;
variables:
  double time(time) ; double node.struct.1.X(time, vec3) ;
  double eig.time(eigensolutions) ; double eig.dCoef(eigensolutions) ;
  double eig.0.Aplus(eig_iSize, eig_iSize) ; double eig.0.Aminus(eig_iSize, eig_iSize) ;
  double eig.1.Aplus(time, vec3) ; double eig.1.Aminus(time, vec3) ; double eig.2.alpha(eig_2_iNVec_out, vec3) ;
data:
  time = 0, 0.1, _, _ ; node.struct.1.X = 1, 2, 3, 1.5, 2, 3, _, _, _, _, _, _ ;
  eig.time = 0, 0.1, 0.2, _ ; eig.dCoef = 0.05, 0.05, 0.05, _ ;
  eig.0.Aplus = 1, 250, -0.05, 3 ; eig.0.Aminus = 1, -250, 0.05, 2 ;
  eig.1.Aplus = 1, 1, 1, 1, 2, -0.05, 2, 1, 250, 2, 2, 3 ; eig.1.Aminus = 1, 1, 1, 1, 2, 0.05, 2, 1, -250, 2, 2, 2 ;
  eig.2.alpha = 0.8, 0.5, 1, -2, 0, 2, 3, 0, 0 ;
}
CDL
ncgen -o "$corpus/netcdf/eig.nc" "$corpus/eig.cdl"
# the estimator's series (fuzz_estimate.cpp's layout: 4 bytes of options, then int16 samples; perl is
# part of every Debian): a decay and a limit cycle sampled as a flow (dt 0.01), the logistic map, and
# a sine quantised to a few levels, each 500 samples
perl -e 'print pack("C4", 0, 192, 128, 2), pack("s<*", map { int(20000 * sin(6.2832 * $_ / 25) * exp(-$_ / 1000)) } 0..499)' \
  > "$corpus/estimate/decay"
perl -e 'print pack("C4", 0, 128, 128, 2), pack("s<*", map { int(20000 * sin(6.2832 * $_ / 25)) } 0..499)' > "$corpus/estimate/cycle"
perl -e '$x = 0.3; print pack("C4", 0, 128, 128, 0), pack("s<*", map { $x = 4 * $x * (1 - $x); int(30000 * ($x - 0.5)) } 0..499)' \
  > "$corpus/estimate/logistic"
perl -e 'print pack("C4", 0, 128, 128, 2), pack("s<*", map { 3 * int(3 * sin(6.2832 * $_ / 40)) } 0..499)' > "$corpus/estimate/quantised"
# inputs that once broke a target, kept as seeds so every run replays them first (fuzz/regressions/TARGET/:
# bdcsvd-deflation, a record of few modes whose R made Eigen 3.4.0's BDCSVD read out of bounds)
for d in "$here"/fuzz/regressions/*/; do cp "$d"* "$corpus/$(basename "$d")/"; done
for f in mbdyn_log mbdyn_out mbdyn_blocks mbdyn_eigenanalysis column_file channel_spec netcdf gzip estimate; do
  echo "fuzz_$f: ${secs} s" >&2
  "$build/fuzz_$f" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=0 \
    "$corpus/$f" 2>"$build/fuzz_$f.log" || { tail -n 40 "$build/fuzz_$f.log" >&2; exit 1; }
  grep -E "^#[0-9]+.*DONE|Done [0-9]+ runs" "$build/fuzz_$f.log" | tail -n 1 >&2 || true
done
# netCDF-4 (HDF5): the same target from a netCDF-4 copy of the run. libhdf5 parses these files; a
# corrupt one can make it loop or free a wild pointer, so the reader reads them only in a child
# process with a time limit, which hands the channels back through a pipe
# (reader/src/isolated_run.hpp). What is fuzzed here is that guard: the target process must
# neither crash, nor hang, nor leak, whatever the child does. A child that crashes
# under the sanitizer still writes libFuzzer's crash-* file (it inherits its death callback) while the
# fuzzer goes on: those files go to a directory of their own and are not failures. libhdf5 leaks on
# its error paths, but only in the child, which leaves by _exit (no leak check): leak detection stays on.
mkdir -p "$corpus/netcdf4" "$build/netcdf4-children"
rm -f "$build/netcdf4-children"/*
nccopy -4 -V time,node,node.struct,node.struct.2,node.struct.2.X,node.struct.2.E "$iso.nc" "$corpus/netcdf4/seed4.nc"
echo "fuzz_netcdf (netCDF-4 seed): ${secs} s" >&2
MLCE_NETCDF4_TIME_LIMIT=3 "$build/fuzz_netcdf" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=0 \
  -artifact_prefix="$build/netcdf4-children/" "$corpus/netcdf4" 2>"$build/fuzz_netcdf4.log" \
  || { tail -n 40 "$build/fuzz_netcdf4.log" >&2; exit 1; }
grep -E "^#[0-9]+.*DONE|Done [0-9]+ runs" "$build/fuzz_netcdf4.log" | tail -n 1 >&2 || true
