#!/usr/bin/env bash
# The whole test suite, from a fresh Debian 12 machine: installs what it
# needs, builds, then runs C++ (ctest), Python (pytest), Blender
# (blender -b) and viewport (Xvfb) tests. Exits non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

bash scripts/install_deps.sh --tests
bash scripts/build.sh

status=0
run() {
  local name=$1; shift
  echo "=== $name"
  local start=$SECONDS
  if "$@"; then echo "=== $name: ok ($((SECONDS - start)) s)"
  else echo "=== $name: FAILED ($((SECONDS - start)) s)"; status=1; fi
}

export POINTNPR_BUILD_DIR=$root/build
# The module is built for Debian's python3 (Blender's); a pyenv/conda python3
# earlier on PATH could not import it.
# .venv-test (scripts/install_deps.sh --tests) is that python3 plus the test
# oracles (tests/requirements.txt), seeing Debian's numpy and pytest.
python=${POINTNPR_PYTHON:-$root/.venv-test/bin/python}
run "C++ tests (ctest)" ctest --test-dir build --output-on-failure -j2
run "Python tests (pytest)" "$python" -m pytest -q tests/python
run "C++ tests under ASan + UBSan (readers with leak checks)" bash scripts/sanitize_tests.sh
run "Reader fuzz smoke (libFuzzer, fixed seed and runs)" bash scripts/fuzz_smoke.sh
if compgen -G "tests/blender/test_*.py" >/dev/null; then
  run "Blender tests (blender -b)" blender -b --factory-startup --python-exit-code 1 \
    --python tests/blender/run.py -- "$root/build"
fi
# The self-contained wheel and the extension zip (auditwheel ~1 min, skipped
# when the package did not change), then the wheel alone in a clean venv.
# With a Python 3.13 here (.venv-py313) the cp313 wheel is required and tested too.
if [[ -x .venv-py313/bin/python ]]; then export POINTNPR_REQUIRE_CP313=1; fi
run "Wheel and extension zip (scripts/build_extension.sh)" bash scripts/build_extension.sh
run "Wheel in a clean venv, Debian's OpenImageIO hidden (pytest tests/wheel)" \
  "$python" -m pytest -q -p no:cacheprovider tests/wheel
# The Blender suite in bpy 4.2 / 4.5 / 5.0 from PyPI (scripts/install_deps.sh
# --tests made the venvs), the extension zip installed by Blender's operator.
# A missing venv or zip, or a run that did not test that version, fails.
bpy_suite() {
  local line=$1 venv=.venv-bpy-$1 log=build/blender-tests-bpy-$1.log zip
  zip=$(ls build/dist/pointnpr-extension-*.zip 2>/dev/null | head -1)
  [[ -x $venv/bin/python ]] || { echo "$venv missing: run scripts/install_deps.sh --tests"; return 1; }
  [[ -n $zip ]] || { echo "no extension zip in build/dist (scripts/build_extension.sh)"; return 1; }
  "$venv/bin/python" tests/blender/run.py --extension "$zip" -- "$root/build" -q >"$log" 2>&1
  local code=$?
  tail -n 15 "$log"
  grep -q "^PointNPR tests in Blender $line\." "$log" || { echo "bpy $line did not run the suite"; return 1; }
  grep -Eq "^[0-9]+ passed" "$log" || { echo "bpy $line: no test passed"; return 1; }
  return $code
}
for line in 4.2 4.5 5.0; do
  run "Blender tests (bpy $line from PyPI, extension installed)" bpy_suite "$line"
done
if [[ -f tests/viewport/viewport_test.py ]]; then
  run "Viewport test (Xvfb)" xvfb-run -a -s "-screen 0 1280x800x24" \
    blender --factory-startup --enable-event-simulate --python-exit-code 1 --python tests/viewport/viewport_test.py -- \
    "$root/build" "$root/build/viewport_screenshot.png"
fi
exit $status
