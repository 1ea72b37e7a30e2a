#!/usr/bin/env bash
# Installs every Debian package that bivo's build, tests, benchmarks and plots need.
# Idempotent: when all packages are present it only checks and returns.
set -euo pipefail

PACKAGES=(
  cmake make g++ pkg-config
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
  python3-numpy
  python3-matplotlib
  # Sharded studies (docs/scaling.md): GNU Parallel, and Slurm + munge for the test that
  # brings up a single-node cluster on localhost.
  parallel
  slurm-wlm
  munge
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq "${missing[@]}"
echo "install-deps: done"
