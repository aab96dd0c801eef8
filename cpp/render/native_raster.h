#pragma once
// Small pieces every native mark backend rasterizes with, in the float
// operations the GL paths use on llvmpipe.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

// Work items over chunks' points: at most kPointGrain points each, in
// chunk and point order, so one big chunk (or many small ones) still
// spreads over the threads, and what items make, joined in item order,
// stays in point order.
inline constexpr uint32_t kPointGrain = 8192;
struct PointItem {
  uint32_t chunk, begin, end;  // points [begin, end) of chunk `chunk`
};
// Appends the items of a chunk's first `count` points.
inline void add_point_items(std::vector<PointItem>& items, uint32_t chunk, uint32_t count) {
  for (uint32_t b = 0; b < count; b += kPointGrain) items.push_back({chunk, b, std::min(count, b + kPointGrain)});
}
// work(item) for every item, on the threads (an item a task).
template <class Work>
void for_each_point_item(const std::vector<PointItem>& items, Work&& work) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) work(items[i]);
  });
}
// What select(item, out) appends for every item, run on the threads and
// joined in item order (the GL's record order) into `out`.
template <class T, class Select>
void select_in_order(const std::vector<PointItem>& items, std::vector<T>& out, Select&& select) {
  std::vector<std::vector<T>> parts(items.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) select(items[i], parts[i]);
  });
  out.clear();
  for (const std::vector<T>& part : parts) out.insert(out.end(), part.begin(), part.end());
}

}  // namespace pointnpr
