#!/usr/bin/env bash
# What the cp313 module (Blender 5.1+) is compiled against, on any Debian 12:
# Debian 13's libpython3.13-dev (the CPython 3.13 headers) and pybind11-dev
# (2.13, which supports 3.13; Debian 12's 2.10 does not), fetched through a
# private apt (scripts/debian13_apt.sh) and unpacked with dpkg-deb under
# build/python313. Nothing is installed on the machine and no 3.13
# interpreter is needed: the module links no libpython. Prints the folder;
# does nothing when the same packages are unpacked already.
#   bash scripts/fetch_python313.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/debian13_apt.sh
build=${1:-build}
out=$build/python313
packages=(libpython3.13-dev pybind11-dev)
recipe="${packages[*]} v1"
if [[ -f $out/recipe && $(cat "$out/recipe") == "$recipe" && -f $out/root/usr/include/python3.13/Python.h ]]; then
  realpath "$out/root"
  exit 0
fi
debian13_apt_init "$build/debian13-apt" >&2
rm -rf "$out"
mkdir -p "$out/debs"
(cd "$out/debs" && debian13_apt download -qq "${packages[@]}") >&2 ||
  { echo "fetch_python313: apt-get download ${packages[*]} (trixie) failed" >&2; exit 1; }
for deb in "$out"/debs/*.deb; do dpkg-deb -x "$deb" "$out/root"; done
# Debian's pyconfig.h only redirects to the multiarch one: put the real one in its place.
cp "$out/root/usr/include/$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)/python3.13/pyconfig.h" \
  "$out/root/usr/include/python3.13/pyconfig.h"
grep -q 'PYBIND11_VERSION_MINOR 13' "$out/root/usr/include/pybind11/detail/common.h" ||
  { echo "fetch_python313: trixie's pybind11 is not 2.13" >&2; exit 1; }
rm -rf "$out/debs"
echo "$recipe" >"$out/recipe"
realpath "$out/root"
