#!/usr/bin/env bash
# Configures and builds everything into ./build (the package lands in build/pointnpr).
set -euo pipefail
cd "$(dirname "$0")/.."
# The cp313 module too where scripts/install_deps.sh --tests made .venv-py313.
py313=()
if [[ -x .venv-py313/bin/python ]]; then py313=(-DPOINTNPR_PYTHON313="$PWD/.venv-py313/bin/python"); fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${py313[@]}" "$@" >/dev/null
cmake --build build -j"$(nproc)"
