#!/usr/bin/env bash
# The core compiles for aarch64: every core source through Debian's cross
# compiler (g++-aarch64-linux-gnu, scripts/install_deps.sh --tests),
# compiled to objects that are thrown away (-c -O0: nothing is linked, so no arm64
# libraries are needed). Highway's foreach_target instantiates every
# kernel for NEON and SVE here, so a hand-written x86 intrinsic or a
# vector type SVE cannot hold (an array, a member) fails the check.
set -euo pipefail
cd "$(dirname "$0")/.."
compiler=${CXX_AARCH64:-aarch64-linux-gnu-g++}
command -v "$compiler" >/dev/null || { echo "check_aarch64: $compiler missing (scripts/install_deps.sh --tests)"; exit 1; }
sources=$(find cpp/core cpp/gl cpp/scene cpp/render cpp/marks cpp/filters cpp/io cpp/geometry -name "*.cpp" | sort)
# Debian's headers for the libraries (glm, Eigen, TBB, Highway, OIIO, libxml2) are
# architecture-independent; /usr/include comes after the cross compiler's own.
echo "$sources" | xargs -P "$(nproc)" -n 1 "$compiler" -std=c++20 -O0 -c -o /dev/null -Wno-psabi -Werror=return-type -Icpp -Ishaders \
  -idirafter /usr/include -idirafter /usr/include/libxml2 -I/usr/include/eigen3 -DGLM_ENABLE_EXPERIMENTAL -DPOINTNPR_SHADER_SOURCE_DIR='""'
echo "check_aarch64: $(echo "$sources" | wc -l) core sources compile for aarch64"
