#!/usr/bin/env bash
# From a fresh Debian 12 machine: installs what PointNPR needs, builds it and
# renders the bundled example scene headless through `blender -b`.
#   scripts/render_example.sh [out.png]   (default: out/example.png)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
out=$(realpath -m "${1:-out/example.png}")

bash scripts/install_deps.sh
bash scripts/build.sh

mkdir -p "$(dirname "$out")"
tmp=$(mktemp -d)
# The add-on is enabled before the file is read (Blender runs its arguments
# in order), so loading it finds the engine and prints no error.
POINTNPR_BUILD_DIR=$root/build blender -b --factory-startup \
  --python-exit-code 1 --python scripts/enable_addon.py blend_examples/urban_lidarhd.blend \
  -o "$tmp/frame_#" -F PNG -f 1
mv "$tmp/frame_1.png" "$out"
rmdir "$tmp"
echo "rendered $out"
