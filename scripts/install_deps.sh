#!/usr/bin/env bash
# Installs what PointNPR needs on Debian 12 (bookworm). Idempotent: does
# nothing when every package is present. Usage: scripts/install_deps.sh [--tests]
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  blender python3 python3-dev python3-numpy pybind11-dev
  libglm-dev libeigen3-dev libnanoflann-dev libtbb-dev
  libopenimageio-dev openimageio-tools
  libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libgles-dev
)
if [[ "${1:-}" == "--tests" ]]; then
  packages+=(libgtest-dev libgmock-dev googletest libbenchmark-dev python3-pytest xvfb xauth glslang-tools)
  packages+=(clang libclang-rt-14-dev)  # scripts/fuzz_smoke.sh (libFuzzer)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
