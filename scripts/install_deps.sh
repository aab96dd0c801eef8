#!/usr/bin/env bash
# Installs what PointNPR needs on Debian 12 (bookworm). Idempotent: does
# nothing when every package is present. Usage: scripts/install_deps.sh [--tests | --bench]
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  blender python3 python3-dev python3-numpy pybind11-dev
  libglm-dev libeigen3-dev libnanoflann-dev libtbb-dev libhwy-dev
  libxml2-dev  # the XML section of E57 files
  zlib1g-dev  # SPZ splat files are gzip streams (io/spz_reader.cpp)
  libzstd-dev  # SPZ version 4's attribute streams are zstd frames (io/spz_reader.cpp)
  libopenimageio-dev openimageio-tools
  libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libgles-dev
  dpkg-dev  # dpkg-deb, dpkg-architecture: scripts/fetch_python313.sh (the cp313 module's headers)
)
if [[ "${1:-}" == "--tests" ]]; then
  packages+=(libgtest-dev libgmock-dev googletest libbenchmark-dev python3-pytest xvfb xauth glslang-tools)
  packages+=(clang libclang-rt-14-dev)  # scripts/fuzz_smoke.sh (libFuzzer)
  packages+=(g++-aarch64-linux-gnu)  # scripts/check_aarch64.sh: the core compiles for ARM
  packages+=(debootstrap)  # scripts/debian13_root.sh: the Debian 13 root of the Python 3.13 (Blender 5.1+) suites
  packages+=(python3-venv)  # .venv-test (test oracles), the bpy venvs, the wheel's build tools and clean-venv test
  packages+=(zstd)  # tests/python/gaussian_reference.py writes SPZ version 4 files with the zstd tool
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
# one venv per Blender line of tests/blender/versions.txt that runs on this
# host (Python 3.11; the 3.13 ones run in scripts/debian13_root.sh's root),
# newest patch of each, pinned; numpy and pytest
# as the official Blender of that line ships them. pip's cache (~/.cache/pip)
# keeps the ~350 MB wheels between runs.
bpy_venvs() {
  local line pin python how
  while read -r line pin python how _; do
    [[ $how == host && $pin == bpy==* ]] || continue
    pin=${pin#bpy==}
    local venv=.venv-bpy-$line
    if [[ -x $venv/bin/python ]] && "$venv/bin/python" -c "import importlib.metadata as m, sys
sys.exit(m.version('bpy') != '$pin' or m.version('numpy') != '1.26.4' or m.version('pytest') != '8.3.4')" 2>/dev/null; then
      continue
    fi
    echo "install_deps: $venv (bpy $pin from PyPI)"
    /usr/bin/python3 -m venv "$venv" </dev/null
    "$venv/bin/python" -m pip install -q "bpy==$pin" numpy==1.26.4 pytest==8.3.4 </dev/null
  done < <(grep -v '^#' tests/blender/versions.txt)
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
fi
