#!/usr/bin/env bash
# Installs the Debian packages mlce needs (only those missing). Run as root on Debian 12.
set -euo pipefail
packages=(build-essential cmake pkg-config libeigen3-dev libboost-program-options-dev libfftw3-dev
          libnanoflann-dev libgtest-dev libgmock-dev googletest libbenchmark-dev nlohmann-json3-dev libfmt-dev
          libnetcdf-dev netcdf-bin zlib1g-dev gnuplot-nox time clang libclang-rt-dev libomp-dev clang-tidy)
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
