#!/usr/bin/env bash
# Installs what PointNPR needs on Debian 12 (bookworm). Idempotent: does
# nothing when every package is present. Usage: scripts/install_deps.sh [--tests | --bench]
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
  packages+=(python3-venv)  # .venv-test (test oracles), the bpy venvs, the wheel's build tools and clean-venv test
fi
if [[ "${1:-}" == "--bench" ]]; then
  packages+=(libbenchmark-dev python3-matplotlib)  # bench/: Google Benchmark, bench/speed_vs_error.py's plots
fi

# Test oracles from PyPI (laspy + lazrs for LAZ), never run-time dependencies:
# a venv over Debian's python3 that still sees its numpy and pytest.
test_venv() {
  if [[ ! -x .venv-test/bin/python ]]; then
    /usr/bin/python3 -m venv --system-site-packages .venv-test
  fi
  if ! .venv-test/bin/python -m pip install -q -r tests/requirements.txt; then
    echo "install_deps: pip install -r tests/requirements.txt failed" >&2
    return 1
  fi
}

# The Blender suite also runs in bpy (Blender as a Python module) from PyPI,
# one venv per Blender line, newest patch of each, pinned; numpy and pytest
# as the official Blender of that line ships them. pip's cache (~/.cache/pip)
# keeps the ~350 MB wheels between runs.
bpy_venvs() {
  local line pin
  for line in 4.2=4.2.23 4.5=4.5.15 5.0=5.0.1; do
    pin=${line#*=}; line=${line%=*}
    local venv=.venv-bpy-$line
    if [[ -x $venv/bin/python ]] && "$venv/bin/python" -c "import importlib.metadata as m, sys
sys.exit(m.version('bpy') != '$pin' or m.version('numpy') != '1.26.4' or m.version('pytest') != '8.3.4')" 2>/dev/null; then
      continue
    fi
    echo "install_deps: $venv (bpy $pin from PyPI)"
    /usr/bin/python3 -m venv "$venv"
    "$venv/bin/python" -m pip install -q "bpy==$pin" numpy==1.26.4 pytest==8.3.4
  done
}

# Blender 5.1+ embed Python 3.13: the cp313 module (cpp/CMakeLists.txt,
# POINTNPR_PYTHON313) needs a 3.13 interpreter, which Debian 12 does not
# package. When one is here (POINTNPR_PYTHON313, python3.13 on PATH, or
# pyenv's), .venv-py313 gets pybind11 >= 2.13 (build time only; Debian's
# 2.10 predates 3.13) and numpy for the wheel's test; scripts/build.sh then
# builds the cp313 module. Without one, the extension admits Blender 4.2 to
# 5.0 only (scripts/build_extension.sh says so).
find_python313() {
  local candidate
  for candidate in "${POINTNPR_PYTHON313:-}" "$(command -v python3.13 || true)" \
                   "$HOME"/.pyenv/versions/3.13*/bin/python3.13; do
    if [[ -n $candidate && -x $candidate ]] &&
       "$candidate" -c 'import sys, venv; sys.exit(sys.version_info[:2] != (3, 13))' 2>/dev/null; then
      echo "$candidate"
      return
    fi
  done
}
py313_venv() {
  local python
  python=$(find_python313)
  if [[ -z $python ]]; then
    echo "install_deps: no Python 3.13 found: the extension will admit Blender 4.2 to 5.0 only (no cp313 wheel)"
    return
  fi
  if [[ ! -x .venv-py313/bin/python ]]; then
    "$python" -m venv .venv-py313
  fi
  .venv-py313/bin/python -m pip install -q pybind11==2.13.6 numpy==2.1.3
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install_deps: all ${#packages[@]} packages present"
else
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  echo "install_deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if [[ "${1:-}" == "--tests" ]]; then
  cd "$(dirname "$0")/.."
  test_venv
  bpy_venvs
  py313_venv
fi
