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
  packages+=(python3-venv)  # .venv-test: the test oracles of tests/requirements.txt
fi

# Test oracles from PyPI (laspy + lazrs for LAZ), never run-time dependencies:
# a venv over Debian's python3 that still sees its numpy and pytest.
test_venv() {
  [[ "${1:-}" == "--tests" ]] || return 0
  local root
  root="$(cd "$(dirname "$0")/.." && pwd)"
  if [[ ! -x "$root/.venv-test/bin/python" ]]; then
    /usr/bin/python3 -m venv --system-site-packages "$root/.venv-test"
  fi
  if ! "$root/.venv-test/bin/python" -m pip install -q -r "$root/tests/requirements.txt"; then
    echo "install_deps: pip install -r tests/requirements.txt failed" >&2
    return 1
  fi
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install_deps: all ${#packages[@]} packages present"
  test_venv "${1:-}"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
test_venv "${1:-}"
