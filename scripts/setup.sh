#!/usr/bin/env bash
# setup.sh: install every Debian bookworm package the project needs (idempotent).
#
# Usage: scripts/setup.sh          (as root, or with sudo available)
# Skips apt entirely when every package is already installed, so it is cheap to call
# from the README's commands and from .ci/run every time.
set -euo pipefail

PACKAGES=(
  # ParaView 5.11 (bundled VTK 9.2) and what its CMake config needs
  paraview paraview-dev python3-paraview
  libhdf5-dev libnetcdf-dev libgdal-dev libavcodec-dev libavformat-dev libavutil-dev
  libswscale-dev libswresample-dev libtheora-dev libogg-dev libglew-dev libgl2ps-dev
  libutfcpp-dev libtiff-dev liblz4-dev mpi-default-dev libdouble-conversion-dev
  qtbase5-dev qttools5-dev libqt5svg5-dev qtbase5-private-dev libqt5opengl5-dev
  qtxmlpatterns5-dev-tools
  # Core
  libtorch-dev python3-torch libopenimageio-dev openimageio-tools libeigen3-dev
  nlohmann-json3-dev libcli11-dev zlib1g-dev liblemon-dev libboost-dev
  # build, tests, benchmarks, charts
  cmake ninja-build g++ python3-dev googletest libgtest-dev libbenchmark-dev
  python3-numpy python3-matplotlib python3-pil clang-format black
  mpi-default-bin  # mpiexec, for Plugin.MPIServer (mpiexec -np 2 pvserver)
  mricron-data  # brain templates (Colin27, INIA19) for Testing/Benchmarks/carry_look_pairs.py
  # rendering without a display
  xvfb xauth
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${PACKAGES[@]}"
echo "setup: done"
