#!/usr/bin/env bash
# The reader/writer C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer
# (GCC), in build-asan: only the test binary is built (the Python module is
# not: the sanitizer runtime cannot be loaded into an uninstrumented python).
# The GL/render tests are left out: under llvmpipe, Mesa/LLVM's own
# allocations show up as leaks, and suppressing them is not worth hiding any
# of ours. Usage: scripts/sanitize_tests.sh [gtest filter, default 'Io*']
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-'Io*'}

# -O1 -g1: readable stacks (file and line), quicker to build (line tables
# build in two thirds of the time of full debug information). GCC's
# -Wmaybe-uninitialized gives false positives under -fsanitize=address (in
# std::regex/std::function here), so that one warning is off in this build
# only; -Werror stays.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPOINTNPR_SANITIZE=ON \
  -DPOINTNPR_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DCMAKE_CXX_FLAGS="-Wno-maybe-uninitialized" >/dev/null
cmake --build build-asan -j2 --target pointnpr_tests

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:check_initialization_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
build-asan/tests/pointnpr_tests --gtest_filter="$filter" --gtest_brief=1
if [[ $# -eq 0 ]]; then
  # The rest (renderer, filters, geometry) under ASan + UBSan too, without
  # leak detection: llvmpipe and LLVM keep allocations alive until exit.
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=0:check_initialization_order=1 \
    POINTNPR_SHADER_DIR=$PWD/shaders build-asan/tests/pointnpr_tests --gtest_filter="-$filter" --gtest_brief=1
fi
