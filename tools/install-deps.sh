#!/usr/bin/env bash
# Installs whatever mollify needs that this Debian machine lacks (apt only).
# Used by the README's commands and by .ci/run.
set -euo pipefail

packages=(
  g++ cmake make            # toolchain
  libgmp-dev libmpfr-dev    # exact arithmetic (GMP rationals, MPFR)
  libboost-dev              # Boost.Multiprecision (mpq_rational, mpfr_float), Boost.Spirit X3
  libeigen3-dev             # double-precision linear algebra (tools/vandermonde-fp, tools/studies)
  libcli11-dev              # command-line parsing
  nlohmann-json3-dev        # catalogue.json and the transcribed seed tables
  libgtest-dev              # tests
  libbenchmark-dev          # benchmarks
  libtomlplusplus-dev       # scene files (toml++, tools/mollify)
  gnuplot-nox               # the PNG plots of `mollify run`
  libfftw3-dev              # FFTs (issue 5)
  libmimalloc-dev           # mollify-gen's malloc (its GMP temporaries; generator/CMakeLists.txt)
  lld                       # the linker (CMakeLists.txt: a fresh build's links 25 s -> 8 s)
  time                      # /usr/bin/time: bench/compile_cost.sh (time and max RSS of a compile)
  pkgconf                   # pkg-config: tests/install_test.sh builds a program with mollify.pc
  gcc gfortran              # issue 19: targets_test compiles the emitted C header and Fortran module
  python3 python3-numpy     # issue 19: targets_test imports the emitted Python module (Debian's /usr/bin/python3)
  python3-dev pybind11-dev  # issue 20: the Python package `mollify` (python/), a pybind11 extension module
  python3-pytest            # issue 20: its tests (tests/python/, python3 -m pytest under ctest)
  clang libclang-rt-14-dev  # issue 20: the libFuzzer harnesses (fuzz/, -DMOLLIFY_FUZZ=ON; libclang_rt.fuzzer)
  libomp-dev                # issue 20: OpenMP for clang (the fuzz build configures the whole tree with clang)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
