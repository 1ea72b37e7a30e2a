#!/usr/bin/env bash
# Installs every Debian package that bivo's build, tests, benchmarks and plots need;
# with --sanitizer also the clang toolchain of `make sanitize` / `make fuzz` (kept apart so
# that `make test`, CI's step, does not download a second compiler).
# Idempotent: when all packages are present it only checks and returns.
set -euo pipefail

PACKAGES=(
  cmake ninja-build make g++ pkg-config
  libeigen3-dev
  libceres-dev
  coinor-libipopt-dev
  libnlopt-cxx-dev libnlopt-dev
  libsuitesparse-dev
  libgtest-dev
  libbenchmark-dev
  libcli11-dev
  nlohmann-json3-dev
  libpng-dev
  # Threads of the odometry's per-pixel passes (odometry/parallel_chunks.h).
  libtbb-dev
  python3-numpy
  python3-matplotlib
  # The Python module (python/, docs/python.md) and its tests: pybind11 with its headers,
  # Python's headers, pytest, and scipy (sparse matrices for bivo.solve_conic, a reference LP).
  pybind11-dev python3-pybind11 python3-dev
  python3-pytest
  python3-scipy
  # The public conic suite's second solver (benchmarks/conic_suite_vs_cvxopt.py, the
  # cross-check of regenerated problems' optima).
  python3-cvxopt
  # Sharded studies (docs/scaling.md): GNU Parallel, and Slurm + munge for the test that
  # brings up a single-node cluster on localhost.
  parallel
  slurm-wlm
  munge
)
# clang for the sanitizer build (ASan + UBSan) and the libFuzzer targets (`make sanitize`,
# `make fuzz`, CI's `make fuzz-ci`), and clang-format for `make format-check` (same LLVM).
if [ "${1:-}" = "--sanitizer" ]; then
  PACKAGES+=(clang libclang-rt-14-dev clang-format)
fi

missing_in() {
  for p in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "$p"
    fi
  done
}
mapfile -t missing < <(missing_in "${PACKAGES[@]}")
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# No recommends: they add a Tk stack (python3-matplotlib; plots use Agg) and GraphBLAS
# (libsuitesparse-dev) that nothing here uses, and minutes of download on a fresh machine.
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
