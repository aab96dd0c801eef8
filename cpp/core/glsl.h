// The common subset of GLSL and C++ in which a mark's kernels are written
// once for both backends (shaders/*_kernels.glsl, *_settings.glsl): the
// shaders #include them, and the native backend includes them here, where
// GLM gives GLSL's types and functions. The subset, so that both compilers
// read the same text with the same float operations:
//  - float literals with an `f` suffix (C++ would compute in double);
//  - no swizzles (vec3(v), not v.xyz; v.x is fine), no out/inout
//    parameters (return a struct), no const arrays;
//  - a file's include guard in the preprocessor both share;
//  - mat_vec(m, v) for mat4 * vec4 (GLM sums the columns in another
//    order than llvmpipe), PRECISE for GLSL's precise;
//  - settings as one block of mat4s and vec4s first, then vec2s and
//    ivec2s, then 4-byte scalars, so the std140 layout and the C++
//    struct's agree (SETTINGS_BLOCK below;
//    gl::check_uniform_block compares the sizes when a program uses one).
// The native file that includes kernels builds with -ffp-contract=off, as
// GLSL on llvmpipe never fuses a product into a sum.
#pragma once

#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

namespace pointnpr::glsl {
using namespace glm;
using uint = std::uint32_t;

inline float uintBitsToFloat(uint v) {
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}
// GLSL's unpackUnorm4x8 (component 0 in the low byte).
inline vec4 unpackUnorm4x8(uint v) {
  vec4 out;
  for (int i = 0; i < 4; ++i) out[i] = float((v >> (8 * i)) & 0xffu) / 255.0f;
  return out;
}
// GLSL's unpackSnorm4x8 (component 0 in the low byte).
inline vec4 unpackSnorm4x8(uint v) {
  vec4 out;
  for (int i = 0; i < 4; ++i) out[i] = clamp(float(int8_t(uint8_t(v >> (8 * i)))) / 127.0f, -1.0f, 1.0f);
  return out;
}
// mat4 * vec4 as llvmpipe computes it: the columns summed in order.
inline vec4 mat_vec(const mat4& m, const vec4& v) { return m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3] * v.w; }
}  // namespace pointnpr::glsl

// GLSL's precise: the native files build with -ffp-contract=off anyway.
#define PRECISE
// A settings block: a uniform block (std140) in GLSL, a struct in C++.
#define SETTINGS_BLOCK(name, binding) struct name {
#define END_SETTINGS_BLOCK(instance) \
  }                                  \
  ;
