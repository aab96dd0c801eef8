#pragma once
// The marks' growth where their points are too sparse for their ink
// (shaders/sparse_growth.glsl, compiled here as the kernels compile it):
// its cap is what the marks' extents allow for.
#include "core/glsl.h"

namespace pointnpr {
namespace glsl {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
namespace {
#include "sparse_growth.glsl"
}  // namespace
#pragma GCC diagnostic pop
}  // namespace glsl

// The most a mark grows (sparse_growth).
constexpr double kMaxSparseGrowth = double(MAX_SPARSE_GROWTH);

}  // namespace pointnpr
