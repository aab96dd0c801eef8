#pragma once
// The seeded randomness of the core and of the marks' native backends
// (the resolution queue's order, mesh sampling, per-point choices): the
// shaders' own functions, shaders/id_hash.glsl, compiled here (the subset
// of core/glsl.h), so CPU and GPU draw the same numbers.
#include "core/glsl.h"

namespace pointnpr {
namespace glsl {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
namespace {
#include "id_hash.glsl"
}  // namespace
#pragma GCC diagnostic pop
}  // namespace glsl

// lowbias32 (Chris Wellons' integer hash).
inline uint32_t hash_u32(uint32_t x) { return glsl::id_hash(x); }
using glsl::id_rand;
using glsl::id_value_noise;

}  // namespace pointnpr
