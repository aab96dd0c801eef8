#!/usr/bin/env bash
# The GPU check (issue 38), for a machine with a GPU, in under 5 minutes:
#  1. builds (scripts/build.sh; skipped with --no-build, the build being current),
#  2. runs the GL backends' parity and determinism tests: each mark's GL
#     passes against its native ones (points, brush splats, stipples,
#     feature strokes), the same bytes frame after frame, with one thread
#     and in another process, every SIMD target of the native brush,
#  3. measures (bench/gpu_check.py): the points mark's 64-bit-atomics
#     compute path against its 32-bit one (the same bytes; reported as not
#     run where the device lacks them, as llvmpipe does), and each mark's
#     frame at 1920x1080 on its GL and native backends, side by side,
#  4. writes the report to REPORT (default build/gpu_check.md) with the
#     device, the tests' outcome and the timings.
# The test command runs it on llvmpipe with --quick (the same tests, one
# timed frame each) so that it keeps working where no GPU is.
#
#     bash bench/gpu_check.sh [--no-build] [--quick] [REPORT]
set -uo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build=1 quick=0 report=$root/build/gpu_check.md
for arg in "$@"; do
  case $arg in
    --no-build) build=0 ;;
    --quick) quick=1 ;;
    *) report=$arg ;;
  esac
done
start=$SECONDS
if [[ $build == 1 ]]; then bash scripts/build.sh || exit 1; fi
python=${POINTNPR_PYTHON:-$root/.venv-test/bin/python}
[[ -x $python ]] || python=/usr/bin/python3
export POINTNPR_BUILD_DIR=$root/build

tests_log=$root/build/gpu_check_tests.log
selection=(tests/python/test_rasterizer.py tests/python/test_marks_brush_splats_native.py
           tests/python/test_marks_stipples_native.py tests/python/test_marks_feature_strokes.py
           tests/python/test_marks_hatching_native.py
           -k "$(echo images_of_compute gl_paths gl_passes exact_path same_bytes deterministic lanes_bytes \
                     vector_bytes two_passes_bytes | sed 's/ / or /g')")
status=0
"$python" -m pytest -q "${selection[@]}" >"$tests_log" 2>&1 || status=1
"$root/build/tests/pointnpr_tests" --gtest_filter='NativeRasterizer.*:StipplesNative.*:BrushSplatsNative.*' \
  >>"$tests_log" 2>&1 || status=1
summary=$(grep -E '^[0-9]+ (passed|failed)|passed|FAILED|PASSED' "$tests_log" | tail -n 4)

frames=5
[[ $quick == 1 ]] && frames=1
PYTHONPATH=$root/build "$python" bench/gpu_check.py "$report" --frames "$frames" || status=1
{
  echo
  echo "Parity and determinism tests ($( [[ $status == 0 ]] && echo passed || echo '**FAILED**'), log: build/gpu_check_tests.log):"
  echo
  echo '```'
  echo "$summary"
  echo '```'
  echo
  echo "Whole check: $((SECONDS - start)) s (\`bash bench/gpu_check.sh $*\`)."
} >>"$report"
echo "gpu_check: report in $report ($((SECONDS - start)) s)"
exit $status
