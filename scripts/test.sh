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
  if "$@"; then echo "=== $name: ok"; else echo "=== $name: FAILED"; status=1; fi
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
if [[ -f tests/viewport/viewport_test.py ]]; then
  run "Viewport test (Xvfb)" xvfb-run -a -s "-screen 0 1280x800x24" \
    blender --factory-startup --python-exit-code 1 --python tests/viewport/viewport_test.py -- \
    "$root/build" "$root/build/viewport_screenshot.png"
fi
exit $status
