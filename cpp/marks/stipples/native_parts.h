#pragma once
// The stipples mark's native passes (native.cpp): the host data they share
// and the image passes that read no settings.
#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "render/host_scratch.h"
#include "render/native_raster.h"

namespace pointnpr::stipples_native {

inline constexpr uint32_t kInfBits = 0x7f800000u;
inline constexpr uint32_t kOutside = 0xffffffffu;  // a point outside the window's fine texture
inline constexpr int kRowGrain = 8;       // rows per work item of the image passes

inline uint32_t bits(float f) { return std::bit_cast<uint32_t>(f); }
inline float from_bits(uint32_t b) { return std::bit_cast<float>(b); }

inline void fetch_add(uint32_t& slot, uint32_t value) {
  std::atomic_ref<uint32_t>(slot).fetch_add(value, std::memory_order_relaxed);
}

// floor and ceil without a library call (without SSE4.1, std::floor is
// one, a large part of a point's cost): exact for every float, since from
// 2^23 on every float is an integer (NaN and infinities pass through).
inline float floor_f(float v) {
  if (!(std::abs(v) < 8388608.0f)) return v;
  const float t = float(int(v));
  return t > v ? t - 1.0f : t;
}
inline float ceil_f(float v) {
  if (!(std::abs(v) < 8388608.0f)) return v;
  const float t = float(int(v));
  return t < v ? t + 1.0f : t;
}

// One chunk as the point passes see it.
struct HostChunk {
  const glm::vec3* positions = nullptr;  // the chunk's first point
  const uint32_t* ids = nullptr;         // its stable point ids
  const uint32_t* order = nullptr;       // queue order (chunk-local indices), or null: all in index order
  const float* opacity = nullptr;        // the dots pass with opacity_draws: its splats' opacities, else null
  uint32_t count = 0;
  uint32_t slot = 0;  // the pass's index of its first point (the per-point arrays')
  const float* spacing = nullptr;  // level_scale spacing or spread_from_spacing: its points' spacing
  float spacing_cell_scale = 0.0f;   // and their cell width over it (spacing_cell_scale)
  float spread_scale = 0.0f;         // spread_from_spacing: their spacing to spread_texels' scale,
  float spread_cap = 0.0f;           // and the largest spacing spread (spread_cap)
  const glm::vec3* normals = nullptr;  // lit_rule share: its points' normals (packed as the GPU's are)
  glm::mat4 view_from_chunk{1.0f};
};

using Item = PointItem;

// The host images of the last frames, kept by the renderer (HostScratch) so
// that a frame does not page in tens of megabytes anew (bounded by the
// largest window and clip).
struct HostBuffers {
  std::vector<uint32_t> hp, tmp, surface, dot_cov, dot_depth, quad, light_count;
  // Per point of the window's pass: its texel (or kOutside) and depth bits
  // from the first projection, and its specular measure (owned, visible).
  std::vector<uint32_t> point_texel, point_depth;
  std::vector<float> point_spec;
  std::vector<float> rgba, depth;
  size_t bytes() const {
    size_t n = 0;
    for (const auto* v : {&hp, &tmp, &surface, &dot_cov, &dot_depth, &quad, &light_count, &point_texel, &point_depth})
      n += held_bytes(*v);
    return n + held_bytes(point_spec) + held_bytes(rgba) + held_bytes(depth);
  }
};
template <class T>
T* sized(std::vector<T>& v, size_t n) {
  if (v.size() < n) v.resize(n);
  return v.data();
}

// Adds the milliseconds since its start to a statistic when it ends.
class PassTimer {
 public:
  PassTimer(std::map<std::string, double>* stats, const char* name)
      : stats_(stats), name_(name), start_(std::chrono::steady_clock::now()) {}
  ~PassTimer() {
    if (stats_)
      (*stats_)[name_] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

 private:
  std::map<std::string, double>* stats_;
  const char* name_;
  std::chrono::steady_clock::time_point start_;
};

// One spreading step over a window's fine texture of `size` texels: out =
// min(in, 3 x 3 minimum of in + step).
void spread_step(glm::ivec2 size, float step, const uint32_t* in, uint32_t* out);
// out = the minimum of `in` over the (2 r + 1)^2 texels around.
void box_min(glm::ivec2 size, const uint32_t* in, uint32_t* out, int r);

}  // namespace pointnpr::stipples_native
