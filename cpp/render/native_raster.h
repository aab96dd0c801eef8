#pragma once
// Small pieces every native mark backend rasterizes with, in the float
// operations the GL paths use on llvmpipe.
#include <atomic>
#include <cstdint>

#include <glm/glm.hpp>

namespace pointnpr {

// floor and ceil as ints for |v| < 2^31 (the caller bounds v): without
// SSE4.1, std::floor is a library call, a large part of a splat's cost.
inline int floor_int(float v) {
  const int i = int(v);
  return i - (float(i) > v);
}
inline int ceil_int(float v) {
  const int i = int(v);
  return i + (float(i) < v);
}

// GLSL's round() on llvmpipe: to the nearest integer, ties to even,
// exactly for every float below 2^51.
inline int64_t round_even(float v) {
  constexpr double kShift = 6755399441055744.0;  // 1.5 x 2^52
  return int64_t((double(v) + kShift) - kShift);
}

// GLSL's mat4 * vec4(p, 1) and mat4 * v: the columns summed in order.
inline glm::vec4 transform(const glm::mat4& m, const glm::vec3& p) {
  return m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
}
inline glm::vec4 transform(const glm::mat4& m, const glm::vec4& p) {
  return m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3] * p.w;
}

// Per-pixel minimum / maximum by compare-and-swap (the shaders' atomicMin
// and atomicMax): only ever lowers (raises) the value.
template <class T>
void fetch_min(T& slot, T value) {
  std::atomic_ref<T> ref(slot);
  T current = ref.load(std::memory_order_relaxed);
  while (value < current && !ref.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
}
template <class T>
void fetch_max(T& slot, T value) {
  std::atomic_ref<T> ref(slot);
  T current = ref.load(std::memory_order_relaxed);
  while (value > current && !ref.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
}

}  // namespace pointnpr
