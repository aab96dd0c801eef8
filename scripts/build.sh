#!/usr/bin/env bash
# Configures and builds everything into ./build (the package lands in
# build/pointnpr, and the cp313 one, for Blender 5.1+, in build/pointnpr-cp313).
set -euo pipefail
cd "$(dirname "$0")/.."
# The cp313 module is built every time, from Debian 13's headers fetched
# into build/python313 (no Python 3.13 needed here).
mkdir -p build
py313_root=$(bash scripts/fetch_python313.sh build)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPOINTNPR_PYTHON313_ROOT="$py313_root" "$@" >/dev/null
cmake --build build -j"$(nproc)"
