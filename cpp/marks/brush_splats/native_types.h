#pragma once
// What the brush_splats native path's parts share (native.cpp orchestrates,
// native_settings.cpp resolves the parameters and the camera-independent
// point frames, native_kernels.cpp holds the lanes compiled once per SIMD
// target): the frame's settings, the splats and the per-bin scratch.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/analysis.h"
#include "marks/points/points.h"
#include "render/gpu_cloud.h"
#include "render/host_scratch.h"
#include "render/mark.h"

namespace pointnpr::brush_native {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint32_t kBatch = 1u << 21;          // splats set up at once without a frame budget (about 300 MiB)
constexpr uint32_t kBatchMin = 1u << 16;       // and at least, with any budget
constexpr uint32_t kGrain = 8192;              // points per setup work item
constexpr uint64_t kKeptFramesMax = 1u << 22;  // points of a cloud whose point frames are kept (60 B each: 240 MiB)
constexpr int kTable = 4096;                   // brush table intervals
constexpr int kPieces = 8;                     // brush polynomial pieces (one 8-lane register of each coefficient)
constexpr int kDegree = 7;                     // and their highest degree
constexpr int kBinSide = 64;                   // screen bins (pixels): splats are up to 2 x 64 px
constexpr int kMaxLanes = 8;                   // the kernels' vectors: at most 8 floats (arrays keep that slack)

// GLSL's mat4 * vec4(p, 1): the columns summed in order.
inline glm::vec4 transform(const glm::mat4& m, const glm::vec3& p) { return m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3]; }
inline glm::vec3 normalized(glm::vec3 v) { return v / std::sqrt(glm::dot(v, v)); }
// What a shader reads of a normal uploaded as snorm8 (render/gpu_cloud.h).
inline glm::vec3 as_uploaded(const glm::vec3& n) { return unpack_normal(pack_normal(n)); }

// The shaders' uniforms, resolved once per frame.
struct Settings {
  glm::vec2 frame{0.0f};    // the whole frame's size
  glm::ivec2 origin{0, 0};  // the tile's
  Rect clip;                // tile pixels
  float near = 0.0f, far = 1.0f;
  bool ortho = false;
  float px_per_unit = 1.0f;
  glm::mat4 projection{1.0f}, view_from_pixel{1.0f};
  bool resolution_size = true, user_eps = false;
  bool splat_size = false;      // size_mode splat: each Gaussian splat's footprint
  bool opacity_weight = false;  // a Gaussian splat's opacity weighs its brush's alpha
  float epsilon = 0.0f, size_scale = 1.0f, world_radius = 0.0f, max_radius_px = 16.0f;
  float support_along = 1.0f, support_across2 = 1.0f;  // brush_support()
  int tangent_frame = 0;
  float angle = 0.0f, jitter = 0.0f;
  uint32_t seed = 0;
  bool two_layers = false;  // layers two (every splat)
  bool clusters = false;
  float small_cluster = 0.0f, elongation_gain = 0.0f, max_stretch = 1.0f;
  float depth_tolerance = 1.0f;
  float shading_strength = 0.0f;
  glm::vec3 light_dir{0.0f, 0.0f, 1.0f};  // towards the light, view space
  // The brush (brush_texture.glsl): centres on the grid and their column.
  int gaussians = 9;
  float cx[9] = {}, cy[9] = {};
  int column[9] = {};
  float amplitude = 1.0f, inv_sx = 1.0f, inv_sy = 1.0f, reach = 1.0f, inv_reach = 1.0f;
  bool sqrt_index = false;  // the table over sqrt(q / reach) (lambda < 1: steep at 0), else over q / reach
  float layer_scale = 1.0f, layer_cos = 1.0f, layer_sin = 0.0f, layer_tint = 0.0f;
  std::vector<float> table;  // exp(-q^lambda / 2) at q = reach t (t^2 with sqrt_index), t = i / kTable (+ 1 pad)
  // Or, where they fit it within 1e-5, kPieces polynomials over t
  // (coefficient d of piece i, in the piece's own 0..1).
  bool pieces = false;
  int degree = kDegree;  // the lowest that fits
  alignas(32) float poly[kDegree + 1][kPieces] = {};
  // The blur (brush_blur.comp): Gaussian taps, depth occlusion.
  int blur_radius = 0;
  float blur_tolerance = 0.0f;
  std::vector<float> blur_weight;  // 2 blur_radius + 1
};
// The frame's settings from the mark's parameters and the camera.
Settings resolve_settings(const MarkContext& ctx, const ParamValues& p);
// exp(-q^lambda / 2), 0 <= q <= reach, as the pieces or the table give it.
float falloff(const Settings& s, float q);

// The camera-independent part of a point's splat (brush_splat() up to the
// view): its axes in chunk space, world radius, stretch, layers and brush
// columns' angles. Kept per cloud (GpuCloud::host_slot) while the
// parameters they follow stay the same, computed for every point at once.
struct PointFrame {
  glm::vec3 t{0.0f}, b{0.0f};  // zero: no normal (the view's axes)
  float radius = 0.0f;         // world, size_scale applied
  float stretch = 1.0f;
  float cs[3] = {}, sn[3] = {};
  bool two = false;
};
static_assert(sizeof(PointFrame) == 60);
struct PointFrames {
  std::string key;                 // the parameters they were made with
  std::vector<PointFrame> frames;  // cloud order
};
// What PointFrames are made from (the cloud's arrays, cloud order).
struct FrameInputs {
  const uint32_t* ids = nullptr;
  const glm::vec3* normals = nullptr;
  const float* r = nullptr;
  const float* eps = nullptr;
  const glm::vec3* axes = nullptr;  // covariance frame's major axes
  const float* splat_r = nullptr;   // size_mode splat (scene/splat_attributes.h)
  const geometry::ClusterShapes* shapes = nullptr;
};
// brush_splat()'s camera-independent part of point `index`.
PointFrame point_frame(const FrameInputs& in, const Settings& s, uint32_t index);

// One visible chunk's host data (index = first + local into the cloud's arrays).
struct Chunk {
  const glm::vec3* positions = nullptr;
  const PointFrame* frames = nullptr;  // kept; null: made per splat from `in`
  FrameInputs in;
  const uint32_t* order = nullptr;  // queue order (chunk-local), or null
  HostColors colors;
  bool shading = false;  // brush_shading(): the colour lit by the splat's plane
  float noise_offset = 0.0f;  // brush_noise_offset(): the least offset toward the camera
  const float* weight = nullptr;  // opacity_weight: the splats' opacities (cloud order), or null (1)
  uint32_t first = 0, count = 0;
  glm::mat4 view{1.0f};
};

// A splat as the tiled fragment shader sees it (its flat inputs).
struct Splat {
  glm::vec3 center{0.0f};  // view space
  glm::vec3 u_axis{0.0f};  // t / (2 radius stretch)
  glm::vec3 v_axis{0.0f};  // b / (2 radius)
  glm::vec3 normal{0.0f};  // the plane's
  glm::vec2 depth_range{0.0f};
  float offset = 0.0f;  // depth_tolerance radii, at least the chunk's noise offset
  glm::vec3 rgb{0.0f};
  float weight = 1.0f;  // the brush's alpha times this (brush_color()'s alpha)
  float cs[3] = {}, sn[3] = {};
  bool two = false;
  glm::ivec2 lo{0}, hi{0};       // local pixels the quad can cover, [lo, hi)
  float wx[4] = {}, wy[4] = {};  // the quad's corners on screen (frame pixels), in order around it
};
// What the bins read of every splat (its box, nearest depth, offset),
// beside the splats: their tests and sort run over 24 bytes a splat, not
// the 148 of a Splat, which only the splats they keep fetch.
struct SplatKey {
  glm::ivec2 lo{0}, hi{0};
  float near = 0.0f, offset = 0.0f;
  explicit SplatKey(const Splat& sp) : lo(sp.lo), hi(sp.hi), near(sp.depth_range.x), offset(sp.offset) {}
  SplatKey() = default;
};

// The per-pixel images over the clip (tile pixels, row-major from clip.min).
struct Images {
  float* surface;  // the depth pass's nearest depth (kMaxLanes of slack past the end)
  float* accum;    // rgb * a, a
  float* reveal;   // transmittance
  float* nearest;  // the blended fragments' nearest depth (where no brush is the surface)
  int stride;
  glm::ivec2 min;
  float* offset = nullptr;  // the surface's splat's blend offset (Splat::offset; 0: no surface), for its rims
};

// Which pass a splat's fragments run: the depth pass, the blend pass, or
// the depth pass that also keeps, with their brush, the fragments the
// blend pass may keep (Candidates), so the blend walks no rows.
enum class Pass { kDepth, kBlend, kBoth };

// A bin's fragments near its surface as the depth pass leaves it after
// each splat. The surface only comes nearer, so a fragment behind it by
// more than the blend's offset stays so; those within are kept with their
// brush, each splat's in one run, for the blend to test against the final
// surface. Bounded: a bin with more blends in a pass of its own.
struct Candidates {
  static constexpr size_t kMax = size_t(1) << 20;  // fragments (20 MiB)
  struct Run {
    uint32_t place, begin, end;  // the splat's place in the bin's list
  };
  // A fragment's pixel, depth, |p|^2 and the brush of each layer, an array
  // each (lanes load at once); kMaxLanes more: the lanes store that many.
  // Grown to the most fragments a bin has kept (a power of two, at most
  // kMax), so what the renderer counts is what it holds; every worker
  // follows the largest (`shared`), so the count settles in the first frame
  // whatever bins each worker happened to draw.
  std::unique_ptr<uint32_t[]> q;
  std::unique_ptr<float[]> depth, length, a1, a2;
  size_t capacity = 0;
  std::atomic<size_t>* shared = nullptr;  // the workers' largest capacity
  size_t count = 0;
  std::vector<Run> runs;
  std::vector<uint32_t> run_at;
  bool full = false;
  void clear() {
    count = 0;
    runs.clear();
    full = false;
  }
  // Room for `n` fragments (n <= kMax), the first `count` kept.
  void reserve(size_t n) {
    if (shared) n = std::max(n, shared->load(std::memory_order_relaxed));
    if (n <= capacity) return;
    const size_t grown = std::min(kMax, std::bit_ceil(std::max(n, size_t(4096))));
    auto move = [this, grown](auto& array) {
      using T = std::remove_reference_t<decltype(array[0])>;
      std::unique_ptr<T[]> bigger(new T[grown + kMaxLanes]);
      if (count > 0) std::copy(array.get(), array.get() + count, bigger.get());
      array = std::move(bigger);
    };
    move(q);
    move(depth);
    move(length);
    move(a1);
    move(a2);
    capacity = grown;
    for (size_t seen = shared ? shared->load() : grown; seen < grown && !shared->compare_exchange_weak(seen, grown);) {
    }
  }
  size_t bytes() const {
    return (capacity > 0 ? 5 * (capacity + kMaxLanes) * sizeof(float) : 0) + held_bytes(runs) + held_bytes(run_at);
  }
};

// A TBB worker's scratch for the bins it draws: their keys in list and
// depth order, and the fragments a bin's depth pass keeps for its blend.
struct BinScratch {
  std::vector<uint64_t> near, sort_scratch;
  std::vector<SplatKey> listed, sorted;
  Candidates candidates;
  size_t bytes() const {
    return held_bytes(near) + held_bytes(sort_scratch) + held_bytes(listed) + held_bytes(sorted) +
           candidates.bytes();
  }
};

// What a bin's passes read: the batch's splats and their keys, the frame's
// settings and images.
struct BinInputs {
  const Splat* splats;
  const SplatKey* keys;
  const Settings* s;
  const Images* im;
};

// The kernels of one SIMD target (native_kernels.cpp). Each computes the
// scalar code's float operations in its order (no FMA, min and max with
// std::min's and std::max's operand order), so every target draws the
// same bytes.
struct Kernels {
  // Splats of the chunk's points [begin, end) (queue order where it has
  // one), each to out[j - begin]; one not drawn gets an empty box.
  void (*set_up)(const Chunk& c, const Settings& s, uint32_t begin, uint32_t end, Splat* out);
  // Pass P over one bin's splats (`list`, n of them, in point order). A
  // kBoth pass whose candidates overflow runs the blend pass apart and
  // returns true.
  bool (*draw_bin)(Pass pass, const BinInputs& in, const Rect& area, const uint32_t* list, size_t n,
                   BinScratch& scratch);
  // The blur's horizontal pass over rows [y0, y1) into the planar sums,
  // and its vertical pass back into the colour (native.cpp, blur()).
  void (*blur_x)(const Settings& s, const float* color, const float* depth, const glm::ivec2* row_span,
                 glm::ivec2 size, float* const* planes, int y0, int y1);
  void (*blur_y)(const Settings& s, float* color, const float* depth, const glm::ivec2* row_span, glm::ivec2 size,
                 const float* const* planes, int y0, int y1);
  int lanes;  // floats per vector
};
// The best target the CPU runs, or (`baseline`) the one every CPU of the
// architecture runs: on x86-64, Highway's scalar one.
Kernels kernels(bool baseline);

}  // namespace pointnpr::brush_native
