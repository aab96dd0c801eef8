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
run "The core compiles for aarch64 (cross compiler, objects thrown away)" bash scripts/check_aarch64.sh
run "The GPU check, on llvmpipe (bench/gpu_check.sh --quick)" bash bench/gpu_check.sh --no-build --quick
if compgen -G "tests/blender/test_*.py" >/dev/null; then
  run "Blender tests (blender -b)" blender -b --factory-startup --python-exit-code 1 \
    --python tests/blender/run.py -- "$root/build"
fi
# The Blender 5.1+ suites (Python 3.13) run in a Debian 13 root: made once
# under build/ (about 40 s), with a venv per line of tests/blender/versions.txt.
versions() { grep -v '^#' tests/blender/versions.txt | awk -v how="$1" 'NF && $4 == how {print $1, $2}'; }
debian13_setup() {
  bash scripts/debian13_root.sh make || return 1
  local line pin
  while read -r line pin; do
    bash scripts/debian13_root.sh venv "$line" "${pin#bpy==}" </dev/null || return 1
  done < <(versions debian13)
}
run "Debian 13 root and its bpy venvs (scripts/debian13_root.sh)" debian13_setup
# The self-contained wheels (cp311, cp313) and the extension zip (auditwheel
# ~1 min a wheel, skipped when the package did not change), then each wheel
# alone in a clean venv: cp311 here with Debian's OpenImageIO hidden, cp313
# in the Debian 13 root, which has neither Debian 12's libraries nor glib.
run "Wheels and extension zip (scripts/build_extension.sh)" bash scripts/build_extension.sh
run "Wheels in clean venvs (pytest tests/wheel)" "$python" -m pytest -q -p no:cacheprovider tests/wheel
# The Blender suite in bpy from PyPI, the extension zip installed by
# Blender's own operator: 4.2 to 5.0 in venvs here (scripts/install_deps.sh
# --tests), 5.1+ in the Debian 13 root. A missing venv or zip, or a run that
# did not test that version, fails.
bpy_suite() {
  local line=$1 how=$2 log=build/blender-tests-bpy-$1.log zip python
  zip=$(ls build/dist/pointnpr-extension-*.zip 2>/dev/null | head -1)
  [[ -n $zip ]] || { echo "no extension zip in build/dist (scripts/build_extension.sh)"; return 1; }
  local launch=()
  if [[ $how == host ]]; then
    python=.venv-bpy-$line/bin/python
    [[ -x $python ]] || { echo "$python missing: run scripts/install_deps.sh --tests"; return 1; }
  else
    python=/opt/venv-bpy-$line/bin/python
    # (its python is a link to the root's /usr/bin/python3.13: only valid in the root)
    [[ -f build/debian13-root/opt/venv-bpy-$line/.pins ]] || { echo "$python missing in the Debian 13 root"; return 1; }
    launch=(bash scripts/debian13_root.sh run)
  fi
  "${launch[@]}" "$python" tests/blender/run.py --extension "$root/$zip" -- "$root/build" -q >"$log" 2>&1
  local code=$?
  tail -n 15 "$log"
  grep -q "^PointNPR tests in Blender $line\." "$log" || { echo "bpy $line did not run the suite"; return 1; }
  grep -Eq "^[0-9]+ passed" "$log" || { echo "bpy $line: no test passed"; return 1; }
  return $code
}
while read -r line pin; do
  # (stdin from /dev/null: nothing the suite runs may eat the loop's lines)
  run "Blender tests (bpy ${pin#bpy==} from PyPI, extension installed)" bpy_suite "$line" host </dev/null
done < <(versions host | grep -v ' debian$')
while read -r line pin; do
  run "Blender tests (bpy ${pin#bpy==} from PyPI in the Debian 13 root, extension installed)" bpy_suite "$line" debian13 </dev/null
done < <(versions debian13)
if [[ -f tests/viewport/viewport_test.py ]]; then
  run "Viewport test (Xvfb)" xvfb-run -a -s "-screen 0 1280x800x24" \
    blender --factory-startup --enable-event-simulate --python-exit-code 1 --python tests/viewport/viewport_test.py -- \
    "$root/build" "$root/build/viewport_screenshot.png"
fi
exit $status
