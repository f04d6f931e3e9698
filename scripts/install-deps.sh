#!/usr/bin/env bash
# Installs the Debian packages mlce needs (only those missing). Run as root on Debian 12.
#   scripts/install-deps.sh           what building, running and testing need (./run demo|build|quick|bench)
#   scripts/install-deps.sh --checks  also the checking tools of ./run test and ./run lint: clang with
#                                     libclang-rt-dev (libFuzzer) and libomp-dev (clang's OpenMP runtime,
#                                     for the estimator's fuzz target), and clang-tidy
set -euo pipefail
packages=(build-essential cmake pkg-config libeigen3-dev libboost-program-options-dev libfftw3-dev
          libnanoflann-dev libgtest-dev libgmock-dev googletest libbenchmark-dev nlohmann-json3-dev libfmt-dev
          libnetcdf-dev netcdf-bin zlib1g-dev gnuplot-nox time)
case "${1:-}" in
  "") ;;
  --checks) packages+=(clang libclang-rt-dev libomp-dev clang-tidy) ;;
  *) echo "install-deps: unknown option '$1' (expected none or --checks)" >&2; exit 2 ;;
esac
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
