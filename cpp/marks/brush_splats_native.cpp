// The brush_splats mark's native path (marks/brush_splats.h): the exact
// (tile-invariant) passes of shaders/brush_splats_tiled.vert/.frag, then
// brush_resolve.comp and brush_blur.comp, on the CPU's threads (TBB), for
// software GL devices, where llvmpipe spends most of the mark's time
// shading the brush's nine Gaussians per fragment, twice.
//
//  1. Setup: every splat (of the chunk's resolution queue when it is on)
//     as brush_common.glsl's brush_splat() and the tiled vertex shader
//     make it: plane, axes, depth range, colour, column angles, and the
//     box of pixels its quad can cover. Batches of at most kBatch splats,
//     eight at a time on AVX2 lanes; the camera-independent part (point
//     frames) kept per cloud between frames.
//  2. Depth pass: each screen bin (render/screen_bins.h) runs its splats
//     nearest first (the minimum does not depend on the order); a
//     fragment's depth comes first (the pixel's ray met with the splat's
//     plane), then the brush of those nearer than the pixel's surface so
//     far or within depth_tolerance radii of it; the nearer ones that cover
//     move the surface. Those within are kept with their brush
//     (Candidates, a run per splat): the surface only comes nearer, so a
//     fragment left behind by more than the tolerance stays so. Once the
//     rest of a bin's splats lie behind its farthest surface, they are
//     dropped.
//  3. Blend (blend_candidates): per bin, in point order, the candidates
//     still within the tolerance of the final surface blend: colour sum,
//     transmittance product, as the GL's blending order. A bin with more
//     candidates than their bound, or a frame of several batches, runs the
//     blend as a pass of its own over the splats (the same tests and float
//     operations, so the same bytes).
//  4. Resolve, blur (with depth occlusion) and upload.
// The brush: exp(-q^lambda / 2) over q / reach (over sqrt(q / reach) for
// lambda < 1, steep at 0) fitted once a frame by eight polynomial pieces,
// or tabulated and interpolated where no piece fits within 1e-5;
// exp(-(qx^l + qy^l) / 2) as the product of the two axes'; within about
// 1e-5 of the shader's, far below the golden images' 2/255. Fragments and
// brushes run on AVX2 lanes where the CPU has them, with the scalar path's
// float operations in its order (no FMA), so the bytes never depend on it.
#include <algorithm>
#include <bit>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Dense>
#include <immintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/hash.h"
#include "core/radix_sort.h"
#include "geometry/analysis.h"
#include "marks/brush_splats.h"
#include "marks/points.h"
#include "render/screen_bins.h"
#include "scene/camera.h"
#include "scene/point_cloud.h"

namespace pointnpr {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// AVX2 helpers inlined into their AVX2 callers.
#define POINTNPR_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline
constexpr uint32_t kBatch = 1u << 21;  // splats set up at once (about 300 MiB)
constexpr uint32_t kGrain = 8192;      // points per setup work item
constexpr uint64_t kKeptFramesMax = 1u << 22;  // points of a cloud whose point frames are kept (60 B each: 240 MiB)
constexpr int kTable = 4096;           // brush table intervals
constexpr int kPieces = 8;             // brush polynomial pieces (one AVX2 register of each coefficient)
constexpr int kDegree = 7;             // and their highest degree
constexpr int kBinSide = 64;           // screen bins (pixels): splats are up to 2 x 64 px

int floor_int(float v) {  // |v| < 2^31 (callers bound it)
  const int i = int(v);
  return i - (float(i) > v);
}

// GLSL's mat4 * vec4(p, 1): the columns summed in order.
glm::vec4 transform(const glm::mat4& m, const glm::vec3& p) { return m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3]; }

glm::vec3 normalized(glm::vec3 v) { return v / std::sqrt(glm::dot(v, v)); }
// What a shader reads of a normal uploaded as snorm8 (render/gpu_cloud.h).
glm::vec3 as_uploaded(const glm::vec3& n) { return unpack_normal(pack_normal(n)); }

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
  float epsilon = 0.0f, size_scale = 1.0f, world_radius = 0.0f, max_radius_px = 16.0f;
  int tangent_frame = 0;
  float angle = 0.0f, jitter = 0.0f;
  uint32_t seed = 0;
  bool two_layers = false;  // layers two (every splat)
  bool clusters = false;
  float small_cluster = 0.0f, elongation_gain = 0.0f, max_stretch = 1.0f;
  float depth_tolerance = 1.0f;
  bool avx2 = false;  // the AVX2 lanes (the CPU has them, and the call did not ask for the scalar ones)
  // The brush (brush_texture.glsl): centres on the grid and their column.
  int gaussians = 9;
  float cx[9] = {}, cy[9] = {};
  int column[9] = {};
  float amplitude = 1.0f, inv_sx = 1.0f, inv_sy = 1.0f, reach = 1.0f, inv_reach = 1.0f;
  bool sqrt_index = false;  // the table over sqrt(q / reach) (lambda < 1: steep at 0), else over q / reach
  float layer_scale = 1.0f, layer_cos = 1.0f, layer_sin = 0.0f, layer_tint = 0.0f;
  std::vector<float> table;  // exp(-q^lambda / 2) at q = reach t (t^2 with sqrt_index), t = i / kTable (+ 1 pad)
  // Or, where they fit it within kPieceError, kPieces polynomials over t
  // (coefficient d of piece i, in the piece's own 0..1).
  bool pieces = false;
  int degree = kDegree;  // the lowest that fits
  alignas(32) float poly[kDegree + 1][kPieces] = {};
};

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
  std::string key;  // the parameters they were made with
  std::vector<PointFrame> frames;  // cloud order
};
// What PointFrames are made from (the cloud's arrays, cloud order).
struct FrameInputs {
  const uint32_t* ids = nullptr;
  const glm::vec3* normals = nullptr;
  const float* r = nullptr;
  const float* eps = nullptr;
  const glm::vec3* axes = nullptr;  // covariance frame's major axes
  const geometry::ClusterShapes* shapes = nullptr;
};

// One visible chunk's host data (index = first + local into the cloud's arrays).
struct Chunk {
  const glm::vec3* positions = nullptr;
  const PointFrame* frames = nullptr;  // kept; null: made per splat from `in`
  FrameInputs in;
  const uint32_t* order = nullptr;  // queue order (chunk-local), or null
  HostColors colors;
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
  float offset = 0.0f;  // depth_tolerance radii
  glm::vec3 rgb{0.0f};
  float cs[3] = {}, sn[3] = {};
  bool two = false;
  glm::ivec2 lo{0}, hi{0};  // local pixels the quad can cover, [lo, hi)
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

// Householder, Eberly, square plate, covariance (brush_common.glsl).
void frame_householder(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
  const float s = n.x >= 0.0f ? 1.0f : -1.0f;
  const float ih = 1.0f / (1.0f + std::abs(n.x));
  t = {-s * n.y, 1.0f - n.y * n.y * ih, -n.y * n.z * ih};
  b = {-s * n.z, -n.y * n.z * ih, 1.0f - n.z * n.z * ih};
}
void tangent_frame(int kind, glm::vec3 n, const glm::vec3* major, glm::vec3& t, glm::vec3& b) {
  if (kind == 1) {
    if (std::abs(n.x) > std::abs(n.y)) t = glm::vec3(-n.z, 0.0f, n.x) / std::sqrt(n.x * n.x + n.z * n.z);
    else t = glm::vec3(0.0f, n.z, -n.y) / std::sqrt(n.y * n.y + n.z * n.z);
    b = glm::cross(n, t);
  } else if (kind == 2) {
    glm::vec3 d(0.57735027f);
    if (std::abs(glm::dot(n, d)) > 0.9f) d = glm::vec3(0.70710678f, -0.70710678f, 0.0f);
    t = normalized(d - glm::dot(d, n) * n);
    b = glm::cross(n, t);
  } else if (kind == 3) {
    const glm::vec3 along = *major - glm::dot(*major, n) * n;
    if (glm::dot(along, along) < 1e-6f) return frame_householder(n, t, b);
    t = normalized(along);
    b = glm::cross(n, t);
  } else {
    frame_householder(n, t, b);
  }
}

// brush_splat()'s camera-independent part.
PointFrame point_frame(const FrameInputs& in, const Settings& s, uint32_t index) {
  PointFrame f;
  float r = s.world_radius;
  if (s.resolution_size) r = in.r[index] + (s.user_eps ? s.epsilon : in.eps[index]);
  f.radius = r * s.size_scale;
  f.two = s.two_layers;
  glm::vec3 n = as_uploaded(in.normals[index]);
  const float len = std::sqrt(glm::dot(n, n));
  if (len > 1e-3f) {
    n /= len;
    glm::vec3 major(0.0f);
    if (s.tangent_frame == 3) major = as_uploaded(in.axes[index]);
    tangent_frame(s.tangent_frame, n, &major, f.t, f.b);
    if (s.clusters && in.shapes->size[index] > 0) {
      f.two = f.two || float(in.shapes->size[index]) < s.small_cluster;
      const float st = std::min(std::pow(std::max(in.shapes->elongation[index], 1.0f), s.elongation_gain), s.max_stretch);
      const glm::vec3 axis = as_uploaded(in.shapes->axis[index]);
      const glm::vec3 along = axis - glm::dot(axis, n) * n;
      if (st > 1.05f && glm::dot(along, along) > 0.01f) {
        f.t = normalized(along);
        f.b = glm::cross(n, f.t);
        f.stretch = st;
      }
    }
  }
  const uint32_t id = in.ids[index];
  float a = s.angle + s.jitter * (2.0f * id_rand(id, 1u, s.seed) - 1.0f);
  for (int col = 0; col < 3; ++col) {
    if (col > 0) a += s.jitter * (2.0f * id_rand(id, uint32_t(col + 1), s.seed) - 1.0f);
    f.cs[col] = std::cos(a);
    f.sn[col] = std::sin(a);
  }
  return f;
}

// A splat's box holds the pixels whose centre lies within kBoxMargin of
// its quad's corners' box on screen: the ray through a centre farther out
// cannot meet the quad (the uv test's rounding moves it by far less), and
// a box so tight lets most splats of a pixel or two be dropped before
// they are rasterized (an empty box: no pixel centre at all). The first
// centre at or past v - margin is ceil(v - 0.5 - margin) = -floor(kBoxLo
// - v); the last at or before v + margin is floor(v - kBoxHi).
constexpr float kBoxMargin = 1.0f / 16.0f;
constexpr float kBoxLo = 0.5f + kBoxMargin, kBoxHi = 0.5f - kBoxMargin;  // (exact)

// brush_splat() and brush_splats_tiled.vert: false where nothing is drawn.
bool setup(const Chunk& c, const Settings& s, uint32_t index, Splat& out) {
  const glm::vec4 v = transform(c.view, c.positions[index]);
  const glm::vec3 center(v);
  const float depth = -v.z;
  if (!(depth >= s.near && depth <= s.far)) return false;
  const PointFrame f = c.frames ? c.frames[index] : point_frame(c.in, s, index);
  const float px_per_unit = s.px_per_unit / (s.ortho ? 1.0f : std::max(depth, 1e-20f));
  const float radius = std::min(f.radius, s.max_radius_px / px_per_unit);
  if (!(radius > 0.0f)) return false;
  const glm::mat3 to_view(c.view);
  const float stretch = f.stretch;
  glm::vec3 tv(1.0f, 0.0f, 0.0f), bv(0.0f, 1.0f, 0.0f);
  if (f.t != glm::vec3(0.0f)) {
    tv = normalized(to_view * f.t);
    bv = normalized(to_view * f.b);
  }
  // The whole splat beyond the near plane (the exact path draws no other).
  const float reach_z = (std::abs(tv.z) * stretch + std::abs(bv.z)) * radius;
  if (-center.z - reach_z < s.near) return false;
  // The box of the quad's corners on screen (frame pixels), less the origin.
  float min_x = kInf, min_y = kInf, max_x = -kInf, max_y = -kInf;
  static constexpr float kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    const float ux = kCorner[k][0], uy = kCorner[k][1];
    const glm::vec3 p = center + (tv * ((ux - 0.5f) * stretch) + bv * (uy - 0.5f)) * (2.0f * radius);
    const glm::vec4 clip = transform(s.projection, p);
    const float wx = (clip.x / clip.w * 0.5f + 0.5f) * s.frame.x, wy = (clip.y / clip.w * 0.5f + 0.5f) * s.frame.y;
    out.wx[k] = wx;
    out.wy[k] = wy;
    min_x = std::min(min_x, wx);
    max_x = std::max(max_x, wx);
    min_y = std::min(min_y, wy);
    max_y = std::max(max_y, wy);
  }
  const float lo_x = float(s.clip.min.x + s.origin.x) - 2.0f, hi_x = float(s.clip.max.x + s.origin.x) + 2.0f;
  const float lo_y = float(s.clip.min.y + s.origin.y) - 2.0f, hi_y = float(s.clip.max.y + s.origin.y) + 2.0f;
  if (!(max_x >= lo_x && min_x <= hi_x && max_y >= lo_y && min_y <= hi_y)) return false;  // also NaN
  // Pixels whose centre lies in the box or within kBoxMargin of it (the
  // uv test decides), clamped to the clip (no int overflow).
  out.lo = {-floor_int(kBoxLo - std::max(min_x, lo_x)) - s.origin.x, -floor_int(kBoxLo - std::max(min_y, lo_y)) - s.origin.y};
  out.hi = {floor_int(std::min(max_x, hi_x) - kBoxHi) + 1 - s.origin.x,
            floor_int(std::min(max_y, hi_y) - kBoxHi) + 1 - s.origin.y};
  out.center = center;
  out.u_axis = tv / (2.0f * radius * stretch);
  out.v_axis = bv / (2.0f * radius);
  out.normal = glm::cross(tv, bv);
  out.depth_range = {depth - reach_z, depth + reach_z};
  out.offset = s.depth_tolerance * radius;
  out.rgb = glm::vec3(c.colors.at(index));
  out.two = f.two;
  std::copy(f.cs, f.cs + 3, out.cs);
  std::copy(f.sn, f.sn + 3, out.sn);
  return true;
}

// Eight lanes of setup()'s steps (setup_avx2).
POINTNPR_AVX2_INLINE __m256 set8(float v) { return _mm256_set1_ps(v); }
// m * (x, y, z, 1), row r, as transform(): ((m0 x + m1 y) + m2 z) + m3.
POINTNPR_AVX2_INLINE __m256 row4_8(const glm::mat4& m, int r, __m256 x, __m256 y, __m256 z) {
  return _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(set8(m[0][r]), x), _mm256_mul_ps(set8(m[1][r]), y)),
                                     _mm256_mul_ps(set8(m[2][r]), z)),
                       set8(m[3][r]));
}
// mat3(m) * (x, y, z), row r.
POINTNPR_AVX2_INLINE __m256 row3_8(const glm::mat4& m, int r, __m256 x, __m256 y, __m256 z) {
  return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(set8(m[0][r]), x), _mm256_mul_ps(set8(m[1][r]), y)),
                       _mm256_mul_ps(set8(m[2][r]), z));
}
POINTNPR_AVX2_INLINE void normalized8(__m256& x, __m256& y, __m256& z) {
  const __m256 dot = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(x, x), _mm256_mul_ps(y, y)), _mm256_mul_ps(z, z));
  const __m256 len = _mm256_sqrt_ps(dot);
  x = _mm256_div_ps(x, len), y = _mm256_div_ps(y, len), z = _mm256_div_ps(z, len);
}
// One coordinate of center + (t a + b_axis b) diameter.
POINTNPR_AVX2_INLINE __m256 corner8(__m256 center, __m256 t, __m256 b_axis, __m256 a, __m256 b, __m256 diameter) {
  return _mm256_add_ps(center, _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(t, a), _mm256_mul_ps(b_axis, b)), diameter));
}
POINTNPR_AVX2_INLINE __m256i floor8(__m256 v) {  // floor_int()
  const __m256i i = _mm256_cvttps_epi32(v);
  return _mm256_add_epi32(i, _mm256_castps_si256(_mm256_cmp_ps(_mm256_cvtepi32_ps(i), v, _CMP_GT_OQ)));
}
POINTNPR_AVX2_INLINE void store8(int32_t* to, __m256i v) { _mm256_store_si256(reinterpret_cast<__m256i*>(to), v); }

// setup() of eight points on AVX2 lanes: the same float operations in the
// same order (glm's left-to-right sums; min and max with std::min's and
// std::max's operand order), so the same splats.
__attribute__((target("avx2"))) void setup_avx2(const Chunk& c, const Settings& s, const uint32_t* index, int n,
                                                Splat* out) {
  alignas(32) float px[8] = {}, py[8] = {}, pz[8] = {}, fr[8] = {}, fs[8] = {};
  alignas(32) float tx[8] = {}, ty[8] = {}, tz[8] = {}, bx[8] = {}, by[8] = {}, bz[8] = {};
  PointFrame made[8];
  const PointFrame* f[8];
  for (int i = 0; i < 8; ++i) {
    const uint32_t j = index[std::min(i, n - 1)];
    const glm::vec3& q = c.positions[j];
    px[i] = q.x, py[i] = q.y, pz[i] = q.z;
    if (c.frames) {
      f[i] = &c.frames[j];
    } else {
      made[i] = point_frame(c.in, s, j);
      f[i] = &made[i];
    }
    fr[i] = f[i]->radius, fs[i] = f[i]->stretch;
    tx[i] = f[i]->t.x, ty[i] = f[i]->t.y, tz[i] = f[i]->t.z;
    bx[i] = f[i]->b.x, by[i] = f[i]->b.y, bz[i] = f[i]->b.z;
  }
  const __m256 x = _mm256_load_ps(px), y = _mm256_load_ps(py), z = _mm256_load_ps(pz);
  const __m256 cx = row4_8(c.view, 0, x, y, z), cy = row4_8(c.view, 1, x, y, z), cz = row4_8(c.view, 2, x, y, z);
  const __m256 sign = _mm256_castsi256_ps(_mm256_set1_epi32(int32_t(0x80000000u)));
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  const __m256 depth = _mm256_xor_ps(cz, sign);
  __m256 ok = _mm256_and_ps(_mm256_cmp_ps(depth, set8(s.near), _CMP_GE_OQ),
                            _mm256_cmp_ps(depth, set8(s.far), _CMP_LE_OQ));
  const __m256 per = s.ortho ? set8(1.0f) : _mm256_max_ps(set8(1e-20f), depth);
  const __m256 px_per_unit = _mm256_div_ps(set8(s.px_per_unit), per);
  const __m256 radius = _mm256_min_ps(_mm256_div_ps(set8(s.max_radius_px), px_per_unit), _mm256_load_ps(fr));
  ok = _mm256_and_ps(ok, _mm256_cmp_ps(radius, _mm256_setzero_ps(), _CMP_GT_OQ));
  // The view's axes where there is no normal (t zero).
  const __m256 t0x = _mm256_load_ps(tx), t0y = _mm256_load_ps(ty), t0z = _mm256_load_ps(tz);
  const __m256 zero = _mm256_setzero_ps(), one = set8(1.0f);
  const __m256 no_normal = _mm256_and_ps(
      _mm256_and_ps(_mm256_cmp_ps(t0x, zero, _CMP_EQ_OQ), _mm256_cmp_ps(t0y, zero, _CMP_EQ_OQ)),
      _mm256_cmp_ps(t0z, zero, _CMP_EQ_OQ));
  __m256 tvx = row3_8(c.view, 0, t0x, t0y, t0z), tvy = row3_8(c.view, 1, t0x, t0y, t0z);
  __m256 tvz = row3_8(c.view, 2, t0x, t0y, t0z);
  normalized8(tvx, tvy, tvz);
  const __m256 b0x = _mm256_load_ps(bx), b0y = _mm256_load_ps(by), b0z = _mm256_load_ps(bz);
  __m256 bvx = row3_8(c.view, 0, b0x, b0y, b0z), bvy = row3_8(c.view, 1, b0x, b0y, b0z);
  __m256 bvz = row3_8(c.view, 2, b0x, b0y, b0z);
  normalized8(bvx, bvy, bvz);
  tvx = _mm256_blendv_ps(tvx, one, no_normal), tvy = _mm256_blendv_ps(tvy, zero, no_normal);
  tvz = _mm256_blendv_ps(tvz, zero, no_normal);
  bvx = _mm256_blendv_ps(bvx, zero, no_normal), bvy = _mm256_blendv_ps(bvy, one, no_normal);
  bvz = _mm256_blendv_ps(bvz, zero, no_normal);
  const __m256 stretch = _mm256_load_ps(fs);
  const __m256 reach_z = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_and_ps(tvz, magnitude), stretch),
                                                     _mm256_and_ps(bvz, magnitude)),
                                       radius);
  ok = _mm256_andnot_ps(_mm256_cmp_ps(_mm256_sub_ps(depth, reach_z), set8(s.near), _CMP_LT_OQ), ok);
  // The quad's corners on screen.
  static constexpr float kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const __m256 diameter = _mm256_mul_ps(set8(2.0f), radius);
  __m256 wx[4], wy[4];
  __m256 min_x = set8(kInf), min_y = set8(kInf), max_x = set8(-kInf), max_y = set8(-kInf);
  for (int k = 0; k < 4; ++k) {
    const __m256 a = _mm256_mul_ps(set8(kCorner[k][0] - 0.5f), stretch), b = set8(kCorner[k][1] - 0.5f);
    const __m256 qx = corner8(cx, tvx, bvx, a, b, diameter), qy = corner8(cy, tvy, bvy, a, b, diameter);
    const __m256 qz = corner8(cz, tvz, bvz, a, b, diameter);
    const __m256 w = row4_8(s.projection, 3, qx, qy, qz);
    const __m256 half = set8(0.5f);
    wx[k] = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_div_ps(row4_8(s.projection, 0, qx, qy, qz), w), half), half),
                          set8(s.frame.x));
    wy[k] = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_div_ps(row4_8(s.projection, 1, qx, qy, qz), w), half), half),
                          set8(s.frame.y));
    min_x = _mm256_min_ps(wx[k], min_x), max_x = _mm256_max_ps(wx[k], max_x);
    min_y = _mm256_min_ps(wy[k], min_y), max_y = _mm256_max_ps(wy[k], max_y);
  }
  const __m256 lo_x = set8(float(s.clip.min.x + s.origin.x) - 2.0f);
  const __m256 hi_x = set8(float(s.clip.max.x + s.origin.x) + 2.0f);
  const __m256 lo_y = set8(float(s.clip.min.y + s.origin.y) - 2.0f);
  const __m256 hi_y = set8(float(s.clip.max.y + s.origin.y) + 2.0f);
  ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(max_x, lo_x, _CMP_GE_OQ), _mm256_cmp_ps(min_x, hi_x, _CMP_LE_OQ)));
  ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(max_y, lo_y, _CMP_GE_OQ), _mm256_cmp_ps(min_y, hi_y, _CMP_LE_OQ)));
  const __m256 box_lo = set8(kBoxLo), box_hi = set8(kBoxHi);
  const __m256i ox = _mm256_set1_epi32(s.origin.x), oy = _mm256_set1_epi32(s.origin.y), one_i = _mm256_set1_epi32(1);
  const __m256i zero_i = _mm256_setzero_si256();
  alignas(32) int32_t lo[2][8], hi[2][8];
  store8(lo[0], _mm256_sub_epi32(_mm256_sub_epi32(zero_i, floor8(_mm256_sub_ps(box_lo, _mm256_max_ps(lo_x, min_x)))), ox));
  store8(lo[1], _mm256_sub_epi32(_mm256_sub_epi32(zero_i, floor8(_mm256_sub_ps(box_lo, _mm256_max_ps(lo_y, min_y)))), oy));
  store8(hi[0], _mm256_sub_epi32(_mm256_add_epi32(floor8(_mm256_sub_ps(_mm256_min_ps(hi_x, max_x), box_hi)), one_i), ox));
  store8(hi[1], _mm256_sub_epi32(_mm256_add_epi32(floor8(_mm256_sub_ps(_mm256_min_ps(hi_y, max_y), box_hi)), one_i), oy));
  const __m256 u_scale = _mm256_mul_ps(diameter, stretch);
  alignas(32) float o[22][8];
  _mm256_store_ps(o[0], cx), _mm256_store_ps(o[1], cy), _mm256_store_ps(o[2], cz);
  _mm256_store_ps(o[3], _mm256_div_ps(tvx, u_scale)), _mm256_store_ps(o[4], _mm256_div_ps(tvy, u_scale));
  _mm256_store_ps(o[5], _mm256_div_ps(tvz, u_scale));
  _mm256_store_ps(o[6], _mm256_div_ps(bvx, diameter)), _mm256_store_ps(o[7], _mm256_div_ps(bvy, diameter));
  _mm256_store_ps(o[8], _mm256_div_ps(bvz, diameter));
  _mm256_store_ps(o[9], _mm256_sub_ps(_mm256_mul_ps(tvy, bvz), _mm256_mul_ps(bvy, tvz)));  // cross(tv, bv)
  _mm256_store_ps(o[10], _mm256_sub_ps(_mm256_mul_ps(tvz, bvx), _mm256_mul_ps(bvz, tvx)));
  _mm256_store_ps(o[11], _mm256_sub_ps(_mm256_mul_ps(tvx, bvy), _mm256_mul_ps(bvx, tvy)));
  _mm256_store_ps(o[12], _mm256_sub_ps(depth, reach_z)), _mm256_store_ps(o[13], _mm256_add_ps(depth, reach_z));
  _mm256_store_ps(o[14], _mm256_mul_ps(set8(s.depth_tolerance), radius));
  for (int k = 0; k < 4; ++k) _mm256_store_ps(o[15 + k], wx[k]);
  alignas(32) float wys[4][8];
  for (int k = 0; k < 4; ++k) _mm256_store_ps(wys[k], wy[k]);
  const int valid = _mm256_movemask_ps(ok);
  for (int i = 0; i < n; ++i) {
    Splat& sp = out[i];
    if (!(valid >> i & 1)) {
      sp.lo = sp.hi = glm::ivec2(0);
      continue;
    }
    sp.lo = {lo[0][i], lo[1][i]};
    sp.hi = {hi[0][i], hi[1][i]};
    sp.center = {o[0][i], o[1][i], o[2][i]};
    sp.u_axis = {o[3][i], o[4][i], o[5][i]};
    sp.v_axis = {o[6][i], o[7][i], o[8][i]};
    sp.normal = {o[9][i], o[10][i], o[11][i]};
    sp.depth_range = {o[12][i], o[13][i]};
    sp.offset = o[14][i];
    for (int k = 0; k < 4; ++k) sp.wx[k] = o[15 + k][i], sp.wy[k] = wys[k][i];
    sp.rgb = glm::vec3(c.colors.at(index[i]));
    sp.two = f[i]->two;
    std::copy(f[i]->cs, f[i]->cs + 3, sp.cs);
    std::copy(f[i]->sn, f[i]->sn + 3, sp.sn);
  }
}

// One layer of a splat's brush, per Gaussian (12 lanes, the last ones
// never reached): its column's angle and its centre turned by it (R c),
// so a fragment's q of every Gaussian is a few products without branches.
constexpr int kLanes12 = 12;
struct Layer {
  float cs[kLanes12], sn[kLanes12];
  float rcx[kLanes12], rcy[kLanes12];
  float column_cs[3], column_sn[3];  // by column
};
Layer layer(const Settings& s, const float* cs, const float* sn) {
  Layer l;
  std::copy(cs, cs + 3, l.column_cs);
  std::copy(sn, sn + 3, l.column_sn);
  for (int k = 0; k < kLanes12; ++k) {
    const int c = k < s.gaussians ? s.column[k] : 0;
    l.cs[k] = cs[c];
    l.sn[k] = sn[c];
    l.rcx[k] = k < s.gaussians ? cs[c] * s.cx[k] - sn[c] * s.cy[k] : 1e30f;
    l.rcy[k] = k < s.gaussians ? sn[c] * s.cx[k] + cs[c] * s.cy[k] : 1e30f;
  }
  return l;
}

float falloff(const Settings& s, float q) {  // exp(-q^lambda / 2), 0 <= q <= reach
  const float t = q * s.inv_reach;
  if (s.pieces) {
    const float x = (s.sqrt_index ? std::sqrt(t) : t) * float(kPieces);
    const int i = std::min(int(x), kPieces - 1);
    const float f = x - float(i);
    float r = s.poly[s.degree][i];
    for (int d = s.degree - 1; d >= 0; --d) r = r * f + s.poly[d][i];
    return r;
  }
  const float at = (s.sqrt_index ? std::sqrt(t) : t) * float(kTable);
  const int i = int(at);
  const float f = at - float(i);
  const float a = s.table[size_t(i)], b = s.table[size_t(i) + 1];
  return a + f * (b - a);
}

// brush_alpha() of brush_texture.glsl; with `stop`, returns as soon as the
// clamped alpha reaches it (the partial sums only grow).
float brush_alpha(const Settings& s, const Layer& l, float u, float v, float stop) {
  float qx[kLanes12], qy[kLanes12];
  for (int k = 0; k < kLanes12; ++k) {
    qx[k] = std::abs(l.cs[k] * u - l.sn[k] * v - l.rcx[k]) * s.inv_sx;
    qy[k] = std::abs(l.sn[k] * u + l.cs[k] * v - l.rcy[k]) * s.inv_sy;
  }
  float sum = 0.0f;
  for (int k = 0; k < s.gaussians; ++k) {
    // Either axis beyond the reach: nothing (also NaN).
    if (!(qx[k] <= s.reach && qy[k] <= s.reach)) continue;
    sum += falloff(s, qx[k]) * falloff(s, qy[k]);
    if (s.amplitude * sum >= stop) break;
  }
  return std::clamp(s.amplitude * sum, 0.0f, 1.0f);
}

// The per-pixel images over the clip (tile pixels, row-major from clip.min).
struct Images {
  float* surface;  // the depth pass's nearest depth
  float* accum;    // rgb * a, a
  float* reveal;   // transmittance
  int stride;
  glm::ivec2 min;
};

// The farthest surface of each 8 x 8 block of a bin, or a bound beyond
// it: a splat whose nearest depth lies behind it under its box has no
// fragment nearer than the surface (depth pass), or near it (blend: behind
// by more than its offset), so it is dropped. The surface only comes
// nearer, so a block's farthest depth stays a bound; it is recomputed once
// kRescan of its rows were touched since (for small splats a rescan costs
// about what rasterizing one does), which drops no splat that the exact
// farthest surface would keep and so changes no byte, only the work.
struct BlockDepths {
  static constexpr int kSide = 8, kBlocks = kBinSide / kSide;  // blocks per axis
  static_assert(kBlocks * kBlocks == 64);
  static constexpr uint8_t kRescan = 4;
  float far[kBlocks * kBlocks];
  uint8_t touched[kBlocks * kBlocks];  // rows touched since the last scan (kRescan: scan at the next look)
  Rect area;
  const Images* im = nullptr;

  BlockDepths() { rescan_all(); }
  void rescan_all() { std::fill(touched, touched + kBlocks * kBlocks, kRescan); }
  float block(int bx, int by) {
    const int b = by * kBlocks + bx;
    if (touched[b] >= kRescan) {
      touched[b] = 0;
      const int x0 = area.min.x + bx * kSide, x1 = std::min(x0 + kSide, area.max.x);
      const int y0 = area.min.y + by * kSide, y1 = std::min(y0 + kSide, area.max.y);
      __m128 m4 = _mm_set1_ps(-kInf);  // (SSE: every x86-64 has it)
      float m = -kInf;
      for (int y = y0; y < y1; ++y) {
        const float* line = im->surface + size_t(y - im->min.y) * size_t(im->stride) - size_t(im->min.x);
        int x = x0;
        for (; x + 4 <= x1; x += 4) m4 = _mm_max_ps(m4, _mm_loadu_ps(line + x));
        for (; x < x1; ++x) m = std::max(m, line[x]);
      }
      alignas(16) float lanes[4];
      _mm_store_ps(lanes, m4);
      far[b] = std::max({m, lanes[0], lanes[1], lanes[2], lanes[3]});
    }
    return far[b];
  }
  // The farthest surface under the pixels [lo, hi) (within the area).
  float under(glm::ivec2 lo, glm::ivec2 hi) {
    lo = glm::max(lo, area.min) - area.min;
    hi = glm::min(hi, area.max) - area.min;
    float m = -kInf;
    for (int by = lo.y / kSide; by <= (hi.y - 1) / kSide; ++by)
      for (int bx = lo.x / kSide; bx <= (hi.x - 1) / kSide; ++bx) m = std::max(m, block(bx, by));
    return m;
  }
  // The farthest surface under the pixels [lo, hi) exactly, for boxes at
  // most 8 pixels wide (the area's rows hold them; the images have a
  // lane's slack past their end).
  float under_exactly(glm::ivec2 lo, glm::ivec2 hi) const {
    lo = glm::max(lo, area.min);
    hi = glm::min(hi, area.max);
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3), width = _mm_set1_epi32(hi.x - lo.x);
    const __m128 first = _mm_castsi128_ps(_mm_cmpgt_epi32(width, lane));
    const __m128 second = _mm_castsi128_ps(_mm_cmpgt_epi32(width, _mm_add_epi32(lane, _mm_set1_epi32(4))));
    const __m128 none = _mm_set1_ps(-kInf);
    __m128 m = none;
    for (int y = lo.y; y < hi.y; ++y) {
      const float* line = im->surface + size_t(y - im->min.y) * size_t(im->stride) + size_t(lo.x - im->min.x);
      m = _mm_max_ps(m, _mm_or_ps(_mm_and_ps(first, _mm_loadu_ps(line)), _mm_andnot_ps(first, none)));
      m = _mm_max_ps(m, _mm_or_ps(_mm_and_ps(second, _mm_loadu_ps(line + 4)), _mm_andnot_ps(second, none)));
    }
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    m = _mm_max_ps(m, _mm_shuffle_ps(m, m, 1));
    return _mm_cvtss_f32(m);
  }
  void touch(int y, int x0, int x1) {  // row y's pixels [x0, x1) may have come nearer
    const int by = (y - area.min.y) / kSide;
    for (int bx = (x0 - area.min.x) / kSide; bx <= (x1 - 1 - area.min.x) / kSide; ++bx) {
      uint8_t& t = touched[by * kBlocks + bx];
      t = uint8_t(std::min(t + 1, int(kRescan)));
    }
  }
};

// A splat's fragments that passed the depth tests, gathered (in the
// order the row loop meets them) so the brush is evaluated for many at a
// time. Each pixel appears once per splat, so deferring its write changes
// nothing another of the splat's fragments reads.
struct Fragments {
  static constexpr int kMax = 256;  // a multiple of the brush's lanes, at least a row (a bin's side)
  static_assert(kMax % 8 == 0 && kMax >= kBinSide);
  int n = 0;
  uint32_t q[kMax + 8];  // (slack: the AVX2 lanes store 8 at a time)
  alignas(32) float u[kMax + 8], v[kMax + 8], depth[kMax + 8];
  // Pass::kBoth: |p|^2 of the pixel's point on the plane, and whether the
  // fragment is nearer than the surface (else only near it).
  alignas(32) float length[kMax + 8];
  int32_t nearer[kMax + 8];
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
  // each (eight lanes load at once); 8 more: the lanes store 8 at a time.
  // (Their pages are touched as used.)
  std::unique_ptr<uint32_t[]> q{new uint32_t[kMax + 8]};
  std::unique_ptr<float[]> depth{new float[kMax + 8]}, length{new float[kMax + 8]};
  std::unique_ptr<float[]> a1{new float[kMax + 8]}, a2{new float[kMax + 8]};
  size_t count = 0;
  std::vector<Run> runs;
  std::vector<uint32_t> run_at;
  bool full = false;
  void clear() {
    count = 0;
    runs.clear();
    full = false;
  }
};

// falloff() on eight lanes, with the pieces of degree kD (0: the
// table); a lane out of reach (`in` clear) reads entry 0 (the pieces: any,
// by its index's low bits). The degree is a constant so that the Horner
// steps unroll and the brush's four falloffs interleave.
template <int kD>
__attribute__((target("avx2"), always_inline)) inline __m256 falloff_avx2(const Settings& s, __m256 q, __m256 in) {
  __m256 t = _mm256_mul_ps(q, _mm256_set1_ps(s.inv_reach));
  if (s.sqrt_index) t = _mm256_sqrt_ps(t);
  if constexpr (kD > 0) {
    const __m256 x = _mm256_mul_ps(t, _mm256_set1_ps(float(kPieces)));
    const __m256i i = _mm256_min_epi32(_mm256_cvttps_epi32(x), _mm256_set1_epi32(kPieces - 1));
    const __m256 f = _mm256_sub_ps(x, _mm256_cvtepi32_ps(i));
    __m256 r = _mm256_permutevar8x32_ps(_mm256_load_ps(s.poly[kD]), i);
    for (int d = kD - 1; d >= 0; --d)
      r = _mm256_add_ps(_mm256_mul_ps(r, f), _mm256_permutevar8x32_ps(_mm256_load_ps(s.poly[d]), i));
    return r;
  }
  const __m256 at = _mm256_mul_ps(t, _mm256_set1_ps(float(kTable)));
  const __m256i i = _mm256_and_si256(_mm256_cvttps_epi32(at), _mm256_castps_si256(in));
  const __m256 f = _mm256_sub_ps(at, _mm256_cvtepi32_ps(i));
  const __m256 a = _mm256_i32gather_ps(s.table.data(), i, 4), b = _mm256_i32gather_ps(s.table.data() + 1, i, 4);
  return _mm256_add_ps(a, _mm256_mul_ps(f, _mm256_sub_ps(b, a)));
}

// brush_alpha()'s |R (u, v) - R c| / sigma along x (kY: y) on eight lanes.
// Its rotated coordinate (R (u, v)).x (kY: .y), shared by a column's Gaussians.
template <bool kY>
__attribute__((target("avx2"), always_inline)) inline __m256 along_avx2(__m256 cs, __m256 sn, __m256 u, __m256 v) {
  return kY ? _mm256_add_ps(_mm256_mul_ps(sn, u), _mm256_mul_ps(cs, v))
            : _mm256_sub_ps(_mm256_mul_ps(cs, u), _mm256_mul_ps(sn, v));
}
__attribute__((target("avx2"), always_inline)) inline __m256 q_avx2(__m256 along, float rc, __m256 inv_sigma) {
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  return _mm256_mul_ps(_mm256_and_ps(_mm256_sub_ps(along, _mm256_set1_ps(rc)), magnitude), inv_sigma);
}

// brush_alpha() for n fragments of one layer. The AVX2 lanes run the same
// float operations in the same order as brush_alpha() (no FMA: the target
// does not enable it), without its early stop: a sum past `stop` is never
// read but as >= stop (depth pass) or clamped to 1 (blend), so every
// decision and byte is the scalar path's on any CPU.
template <int kD>
__attribute__((target("avx2"))) void brush_alphas_avx2(const Settings& s, const Layer& l, const float* u,
                                                        const float* v, int n, float* out) {
  const __m256 inv_sx = _mm256_set1_ps(s.inv_sx), inv_sy = _mm256_set1_ps(s.inv_sy);
  const __m256 reach = _mm256_set1_ps(s.reach), amplitude = _mm256_set1_ps(s.amplitude);
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  // Eight fragments at a time (the arrays are padded to 8); each column's
  // rotated coordinates once, for its Gaussians.
  const int columns = std::min(s.gaussians, 3);
  for (int j = 0; j < n; j += 8) {
    const __m256 u8 = _mm256_load_ps(u + j), v8 = _mm256_load_ps(v + j);
    __m256 ax[3], ay[3];
    for (int c = 0; c < columns; ++c) {
      const __m256 cs = _mm256_set1_ps(l.column_cs[c]), sn = _mm256_set1_ps(l.column_sn[c]);
      ax[c] = along_avx2<false>(cs, sn, u8, v8);
      ay[c] = along_avx2<true>(cs, sn, u8, v8);
    }
    __m256 sum = zero;
    for (int k = 0; k < s.gaussians; ++k) {
      const int c = s.column[k];
      const __m256 qx = q_avx2(ax[c], l.rcx[k], inv_sx), qy = q_avx2(ay[c], l.rcy[k], inv_sy);
      const __m256 in = _mm256_and_ps(_mm256_cmp_ps(qx, reach, _CMP_LE_OQ), _mm256_cmp_ps(qy, reach, _CMP_LE_OQ));
      if (_mm256_movemask_ps(in) == 0) continue;
      const __m256 fx = falloff_avx2<kD>(s, qx, in), fy = falloff_avx2<kD>(s, qy, in);
      sum = _mm256_add_ps(sum, _mm256_and_ps(_mm256_mul_ps(fx, fy), in));
    }
    _mm256_store_ps(out + j, _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(amplitude, sum), zero), one));
  }
}

const bool kCpuHasAvx2 = __builtin_cpu_supports("avx2");

void brush_alphas(const Settings& s, const Layer& l, const float* u, const float* v, int n, float stop, float* out) {
  if (s.avx2) {
    switch (s.pieces ? s.degree : 0) {
      case 3: return brush_alphas_avx2<3>(s, l, u, v, n, out);
      case 4: return brush_alphas_avx2<4>(s, l, u, v, n, out);
      case 5: return brush_alphas_avx2<5>(s, l, u, v, n, out);
      case 6: return brush_alphas_avx2<6>(s, l, u, v, n, out);
      case 7: return brush_alphas_avx2<7>(s, l, u, v, n, out);
      default: return brush_alphas_avx2<0>(s, l, u, v, n, out);
    }
  }
  for (int j = 0; j < n; ++j) out[j] = brush_alpha(s, l, u[j], v[j], stop);
}

// A fragment's blend of its brush's alpha a (a2: the second layer's).
inline void blend(const Splat& sp, const Settings& s, const Images& im, size_t q, float a, float a2) {
  glm::vec3 rgb = sp.rgb;
  if (sp.two) {
    const glm::vec3 rgb2 = s.layer_tint >= 0.0f ? rgb * (1.0f - s.layer_tint) + glm::vec3(s.layer_tint)
                                                : rgb * (1.0f + s.layer_tint);
    const float total = a2 + a * (1.0f - a2);
    rgb = total > 0.0f ? (rgb2 * a2 + rgb * a * (1.0f - a2)) / total : rgb;
    a = total;
  }
  if (!(a >= kBrushCut)) return;
  float* acc = im.accum + 4 * q;
  acc[0] += rgb.r * a;
  acc[1] += rgb.g * a;
  acc[2] += rgb.b * a;
  acc[3] += a;
  im.reveal[q] *= 1.0f - a;
}

// For each 8-bit mask, the lanes it keeps in order (then zeros): a
// permutation packing them to the front.
struct PackTable {
  alignas(32) int32_t lanes[256][8];
  constexpr PackTable() : lanes{} {
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int i = 0; i < 8; ++i)
        if (m >> i & 1) lanes[m][k++] = i;
    }
  }
};
constexpr PackTable kPack;

// shade()'s coverage test and writes on AVX2 lanes: the same float
// operations; the covering fragments move the surface (the depth pass;
// kBoth: those nearer than it) and, with `out`, join the candidates packed
// by a permutation.
template <Pass P>
__attribute__((target("avx2"))) void keep_covering_avx2(const Splat& sp, Fragments& f, const float* a1,
                                                         const float* a2, const Images& im, Candidates* out) {
  const int n = f.n;
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 cut = _mm256_set1_ps(kBrushCut), one = _mm256_set1_ps(1.0f);
  size_t recorded = out ? out->count : 0;
  for (int j = 0; j < n; j += 8) {
    const __m256 a = _mm256_loadu_ps(a1 + j);
    __m256 covers = _mm256_cmp_ps(a, cut, _CMP_GE_OQ);
    __m256 b = _mm256_setzero_ps();
    if (sp.two) {
      b = _mm256_loadu_ps(a2 + j);
      const __m256 total = _mm256_add_ps(b, _mm256_mul_ps(a, _mm256_sub_ps(one, b)));
      covers = _mm256_or_ps(covers, _mm256_or_ps(_mm256_cmp_ps(b, cut, _CMP_GE_OQ), _mm256_cmp_ps(total, cut, _CMP_GE_OQ)));
    }
    covers = _mm256_and_ps(covers, _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(n - j), lane)));
    const int mask = _mm256_movemask_ps(covers);
    if (mask == 0) continue;
    int moves = mask;
    if (P == Pass::kBoth) {  // (nearer: 1 or all bits set)
      const __m256i nearer = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(f.nearer + j));
      moves &= ~_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(nearer, _mm256_setzero_si256())));
    }
    for (int m = moves; m != 0; m &= m - 1) {
      const int i = j + __builtin_ctz(unsigned(m));
      im.surface[f.q[i]] = f.depth[i];
    }
    if (!out) continue;
    const __m256i pack = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.lanes[mask]));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out->q.get() + recorded),
                        _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(f.q + j)), pack));
    _mm256_storeu_ps(out->depth.get() + recorded, _mm256_permutevar8x32_ps(_mm256_loadu_ps(f.depth + j), pack));
    _mm256_storeu_ps(out->length.get() + recorded, _mm256_permutevar8x32_ps(_mm256_loadu_ps(f.length + j), pack));
    _mm256_storeu_ps(out->a1.get() + recorded, _mm256_permutevar8x32_ps(a, pack));
    _mm256_storeu_ps(out->a2.get() + recorded, _mm256_permutevar8x32_ps(b, pack));
    recorded += size_t(__builtin_popcount(unsigned(mask)));
  }
  if (out) out->count = recorded;
  f.n = 0;
}

// The brush of a splat's gathered fragments, then their depth (depth
// pass), blend, or both: depth, and the candidates that cover.
template <Pass P>
void shade(const Splat& sp, const Settings& s, const Layer& first, const Layer& second, Fragments& f,
           const Images& im, Candidates* out) {
  constexpr bool kDepth = P == Pass::kDepth;
  const int n = f.n;
  if (n == 0) return;
  for (int j = n; j < ((n + 7) & ~7); ++j) f.u[j] = f.v[j] = 0.0f;  // whole groups of lanes
  const float stop = kDepth ? kBrushCut : 1.0f;
  alignas(32) float a1[Fragments::kMax], a2[Fragments::kMax];
  brush_alphas(s, first, f.u, f.v, n, stop, a1);
  if (sp.two) {
    alignas(32) float u2[Fragments::kMax], v2[Fragments::kMax];
    for (int j = 0; j < ((n + 7) & ~7); ++j) {
      u2[j] = (f.u[j] - 0.5f) / s.layer_scale + 0.5f;
      v2[j] = (f.v[j] - 0.5f) / s.layer_scale + 0.5f;
    }
    brush_alphas(s, second, u2, v2, n, stop, a2);
  }
  if (P == Pass::kBlend) {
    for (int j = 0; j < n; ++j) blend(sp, s, im, f.q[j], a1[j], sp.two ? a2[j] : 0.0f);
    f.n = 0;
    return;
  }
  // Room for the candidates, or none kept from here on.
  if (P == Pass::kBoth && !out->full && out->count + size_t(n) > Candidates::kMax) out->full = true;
  const bool record = P == Pass::kBoth && !out->full;
  if (s.avx2) return keep_covering_avx2<P>(sp, f, a1, a2, im, record ? out : nullptr);
  size_t recorded = record ? out->count : 0;
  for (int j = 0; j < n; ++j) {
    const float a = a1[j], b = sp.two ? a2[j] : 0.0f;
    // (Neither layer reached the cut alone, in the depth pass: both sums are whole.)
    const bool covers = a >= kBrushCut || (sp.two && (b >= kBrushCut || b + a * (1.0f - b) >= kBrushCut));
    if (!covers) continue;
    if (kDepth || f.nearer[j]) im.surface[f.q[j]] = f.depth[j];
    if (record) {
      out->q[recorded] = f.q[j];
      out->depth[recorded] = f.depth[j];
      out->length[recorded] = f.length[j];
      out->a1[recorded] = a;
      out->a2[recorded] = b;
      ++recorded;
    }
  }
  if (record) out->count = recorded;
  f.n = 0;
}

// A perspective splat's row: the numbers its pixels' lanes need.
struct RowLanes {
  float plane, d0, dx, u0, ux, v0, vx, cu, cv, near_d, far_d, offset;
  glm::vec3 hx, hr;
  int origin_x;
  const float* surface;  // the row's, by local x (the images hold a lane's slack past their end)
  size_t line;           // the row's first pixel, by local x
};

// The row's pixels [x0, x1), eight at a time without branches (the
// compiler's vectors): on the quad, and nearer than the surface (depth
// pass) or near it (blend: within the offset moved toward the camera along
// the pixel's ray, at most to the camera: depth (1 - offset / max(|p|,
// depth)) <= surface, as |p| (depth - surface) <= depth offset, squared).
// Those kept go to `f` in row order; returns whether one is nearer than
// the surface (Pass::kBoth keeps those near it, as the blend).
template <Pass P>
__attribute__((always_inline)) inline bool row_lanes(const RowLanes& r, int x0, int x1, Fragments& f) {
  constexpr bool kDepth = P == Pass::kDepth;
  constexpr int kLanes = 8;
  int any_nearer = 0;
  for (int xs = x0; xs < x1; xs += kLanes) {
    const int n = std::min(kLanes, x1 - xs);
    float us[kLanes], vs[kLanes], ds[kLanes], ls[kLanes];
    int keep[kLanes], nearer[kLanes];
    const float* surface = r.surface + xs;
    for (int i = 0; i < kLanes; ++i) {
      const float xc = float(xs + i + r.origin_x) + 0.5f;
      const float t = r.plane / (r.d0 + xc * r.dx);
      const float pz = t * (r.hr.z + xc * r.hx.z);
      const float u = t * (r.u0 + xc * r.ux) + r.cu, v = t * (r.v0 + xc * r.vx) + r.cv;
      us[i] = u;
      vs[i] = v;
      const float depth = std::min(std::max(-pz, r.near_d), r.far_d);
      ds[i] = depth;
      // Off the quad, or the plane seen edge on (not finite): nothing.
      const int on = (i < n) & (std::abs(pz) < 3.0e38f) & (u >= 0.0f) & (u <= 1.0f) & (v >= 0.0f) & (v <= 1.0f);
      nearer[i] = on & (depth < surface[i]);
      if (kDepth) {
        keep[i] = nearer[i];
      } else {
        const glm::vec3 p = (r.hx * xc + r.hr) * t;  // h t
        const float behind = depth - surface[i], reach = depth * r.offset;
        ls[i] = glm::dot(p, p);
        keep[i] = on & ((depth <= surface[i]) | ((depth - r.offset <= surface[i]) & (ls[i] * behind * behind <= reach * reach)));
      }
    }
    for (int i = 0; i < n; ++i) {
      f.q[f.n] = uint32_t(r.line + size_t(xs + i));
      f.u[f.n] = us[i];
      f.v[f.n] = vs[i];
      f.depth[f.n] = ds[i];
      if (P == Pass::kBoth) {
        f.length[f.n] = ls[i];
        f.nearer[f.n] = nearer[i];
      }
      any_nearer |= nearer[i];
      f.n += keep[i];
    }
  }
  return any_nearer;
}

// row_lanes() on AVX2 lanes: the same float operations in the same order
// (the max and min with std::max's and std::min's operand order), the kept
// lanes packed by a permutation.
template <Pass P>
__attribute__((target("avx2"))) inline bool row_avx2(const RowLanes& r, int x0, int x1, Fragments& f) {
  constexpr bool kDepth = P == Pass::kDepth;
  int any_nearer = 0;
  int kept = f.n;  // (a local: stores to the arrays of f could alias f.n)
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  const __m256 sign = _mm256_castsi256_ps(_mm256_set1_epi32(int32_t(0x80000000u)));
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), huge = _mm256_set1_ps(3.0e38f);
  const __m256 plane = _mm256_set1_ps(r.plane), d0 = _mm256_set1_ps(r.d0), dx = _mm256_set1_ps(r.dx);
  const __m256 u0 = _mm256_set1_ps(r.u0), ux = _mm256_set1_ps(r.ux), cu = _mm256_set1_ps(r.cu);
  const __m256 v0 = _mm256_set1_ps(r.v0), vx = _mm256_set1_ps(r.vx), cv = _mm256_set1_ps(r.cv);
  const __m256 hrz = _mm256_set1_ps(r.hr.z), hxz = _mm256_set1_ps(r.hx.z);
  const __m256 near_d = _mm256_set1_ps(r.near_d), far_d = _mm256_set1_ps(r.far_d), offset = _mm256_set1_ps(r.offset);
  for (int xs = x0; xs < x1; xs += 8) {
    const int n = std::min(8, x1 - xs);
    const __m256 xc =
        _mm256_add_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(xs + r.origin_x), lane)),
                      _mm256_set1_ps(0.5f));
    const __m256 t = _mm256_div_ps(plane, _mm256_add_ps(d0, _mm256_mul_ps(xc, dx)));
    const __m256 pz = _mm256_mul_ps(t, _mm256_add_ps(hrz, _mm256_mul_ps(xc, hxz)));
    const __m256 u = _mm256_add_ps(_mm256_mul_ps(t, _mm256_add_ps(u0, _mm256_mul_ps(xc, ux))), cu);
    const __m256 v = _mm256_add_ps(_mm256_mul_ps(t, _mm256_add_ps(v0, _mm256_mul_ps(xc, vx))), cv);
    const __m256 depth = _mm256_min_ps(far_d, _mm256_max_ps(near_d, _mm256_xor_ps(pz, sign)));
    __m256 keep = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(n), lane));
    keep = _mm256_and_ps(keep, _mm256_cmp_ps(_mm256_and_ps(pz, magnitude), huge, _CMP_LT_OQ));
    keep = _mm256_and_ps(keep, _mm256_and_ps(_mm256_cmp_ps(u, zero, _CMP_GE_OQ), _mm256_cmp_ps(u, one, _CMP_LE_OQ)));
    keep = _mm256_and_ps(keep, _mm256_and_ps(_mm256_cmp_ps(v, zero, _CMP_GE_OQ), _mm256_cmp_ps(v, one, _CMP_LE_OQ)));
    const __m256 surface = _mm256_loadu_ps(r.surface + xs);
    const __m256 nearer = _mm256_and_ps(keep, _mm256_cmp_ps(depth, surface, _CMP_LT_OQ));
    any_nearer |= _mm256_movemask_ps(nearer);
    __m256 length = _mm256_setzero_ps();
    if (kDepth) {
      keep = nearer;
    } else {
      const __m256 px = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(r.hx.x), xc), _mm256_set1_ps(r.hr.x)), t);
      const __m256 py = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(r.hx.y), xc), _mm256_set1_ps(r.hr.y)), t);
      const __m256 pw = _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(hxz, xc), hrz), t);
      length = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(px, px), _mm256_mul_ps(py, py)), _mm256_mul_ps(pw, pw));
      const __m256 behind = _mm256_sub_ps(depth, surface), reach = _mm256_mul_ps(depth, offset);
      const __m256 moved = _mm256_and_ps(
          _mm256_cmp_ps(_mm256_sub_ps(depth, offset), surface, _CMP_LE_OQ),
          _mm256_cmp_ps(_mm256_mul_ps(_mm256_mul_ps(length, behind), behind), _mm256_mul_ps(reach, reach), _CMP_LE_OQ));
      keep = _mm256_and_ps(keep, _mm256_or_ps(_mm256_cmp_ps(depth, surface, _CMP_LE_OQ), moved));
    }
    const int mask = _mm256_movemask_ps(keep);
    if (mask == 0) continue;
    const __m256i pack = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.lanes[mask]));
    const __m256i q = _mm256_add_epi32(_mm256_set1_epi32(int32_t(r.line + size_t(xs))), lane);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(f.q + kept), _mm256_permutevar8x32_epi32(q, pack));
    _mm256_storeu_ps(f.u + kept, _mm256_permutevar8x32_ps(u, pack));
    _mm256_storeu_ps(f.v + kept, _mm256_permutevar8x32_ps(v, pack));
    _mm256_storeu_ps(f.depth + kept, _mm256_permutevar8x32_ps(depth, pack));
    if (P == Pass::kBoth) {
      _mm256_storeu_ps(f.length + kept, _mm256_permutevar8x32_ps(length, pack));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(f.nearer + kept),
                          _mm256_permutevar8x32_epi32(_mm256_castps_si256(nearer), pack));
    }
    kept += __builtin_popcount(unsigned(mask));
  }
  f.n = kept;
  return any_nearer != 0;
}

// A splat's fragments over `area` in pass P (kBoth: its candidates to
// `out`, as one run, by its place in the bin's list). The depth passes
// mark the blocks of the rows where a fragment was nearer than the
// surface. kAvx2: flattened into rasterize_avx2 with the rows' lanes, so
// their constants are set once a splat, not once a row (most splats are
// a few pixels wide and high).
// (GCC, flattening, takes `second` for unset where only sp.two reads it, set then.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
template <Pass P, bool kOrtho, bool kAvx2>
void rasterize_splat(uint32_t place, const Splat& sp, const Settings& s, const Rect& area, const Images& im,
                     BlockDepths& blocks, Candidates* out) {
  constexpr bool kDepth = P == Pass::kDepth;
  const glm::ivec2 lo = glm::max(sp.lo, area.min), hi = glm::min(sp.hi, area.max);
  if (lo.x >= hi.x || lo.y >= hi.y) return;
  const size_t begin = P == Pass::kBoth ? out->count : 0;
  Fragments frags;
  // The layers at the first fragments that need the brush (most of a
  // depth pass's splats have none: they lie behind).
  Layer first, second;
  bool layers_ready = false;
  auto flush = [&] {
    if (frags.n == 0) return;
    if (!layers_ready) {
      layers_ready = true;
      first = layer(s, sp.cs, sp.sn);
      if (sp.two) {
        float cs[3], sn[3];  // turned by the layer angle: cos(t + l), sin(t + l)
        for (int c = 0; c < 3; ++c) {
          cs[c] = sp.cs[c] * s.layer_cos - sp.sn[c] * s.layer_sin;
          sn[c] = sp.sn[c] * s.layer_cos + sp.cs[c] * s.layer_sin;
        }
        second = layer(s, cs, sn);
      }
    }
    shade<P>(sp, s, first, second, frags, im, out);
  };
  const float plane = glm::dot(sp.center, sp.normal);
  const glm::vec4 col_x = s.view_from_pixel[0], col_y = s.view_from_pixel[1], col_w = s.view_from_pixel[3];
  // Perspective: the pixel's ray h (homogeneous, linear in the frame pixel)
  // meets the plane at p = h.xyz t, t = plane / dot(h.xyz, n) (h.w cancels):
  // the ray's dot products with n, the axes and z are linear along a row.
  const glm::vec3 hx(col_x);
  const float dx = glm::dot(hx, sp.normal), ux = glm::dot(hx, sp.u_axis), vx = glm::dot(hx, sp.v_axis);
  const float cu = 0.5f - glm::dot(sp.center, sp.u_axis), cv = 0.5f - glm::dot(sp.center, sp.v_axis);
  const float near_d = sp.depth_range.x, far_d = sp.depth_range.y;
  // The quad's edges met with each row through the pixel centres: the
  // row's span, a pixel wider each side (the uv test decides, so the
  // slope's rounding moves no pixel on or off the quad).
  float edge_x[4], edge_y[4], edge_lo[4], edge_hi[4], edge_slope[4], flat_min[4], flat_max[4];
  for (int e = 0; e < 4; ++e) {
    const float xa = sp.wx[e], ya = sp.wy[e], xb = sp.wx[(e + 1) & 3], yb = sp.wy[(e + 1) & 3];
    edge_x[e] = xa;
    edge_y[e] = ya;
    edge_lo[e] = std::min(ya, yb);
    edge_hi[e] = std::max(ya, yb);
    edge_slope[e] = ya == yb ? 0.0f : (xb - xa) / (yb - ya);
    // A level edge on the row: both its ends.
    flat_min[e] = ya == yb ? std::min(xa, xb) : kInf;
    flat_max[e] = ya == yb ? std::max(xa, xb) : -kInf;
  }
  // Four rows at a time on SSE lanes (every x86-64 has them; min and max
  // with std::min's and std::max's operand order): each row's first pixel
  // and its end past the last, frame pixels (none: x_min > x_max).
  constexpr int kRows = kBinSide + 4;
  alignas(16) int32_t row_x0[kRows], row_x1[kRows];
  {
    auto floor4 = [](__m128 v) {  // floor_int()
      const __m128i i = _mm_cvttps_epi32(v);
      return _mm_add_epi32(i, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(i), v)));
    };
    const __m128 half = _mm_set1_ps(0.5f);
    for (int y = lo.y; y < hi.y; y += 4) {
      const __m128 yc = _mm_add_ps(_mm_cvtepi32_ps(_mm_add_epi32(_mm_set1_epi32(y + s.origin.y), _mm_setr_epi32(0, 1, 2, 3))), half);
      __m128 x_min = _mm_set1_ps(kInf), x_max = _mm_set1_ps(-kInf);
      for (int e = 0; e < 4; ++e) {
        const __m128 meets = _mm_and_ps(_mm_cmple_ps(_mm_set1_ps(edge_lo[e]), yc), _mm_cmple_ps(yc, _mm_set1_ps(edge_hi[e])));
        const __m128 xc = _mm_add_ps(_mm_set1_ps(edge_x[e]), _mm_mul_ps(_mm_sub_ps(yc, _mm_set1_ps(edge_y[e])), _mm_set1_ps(edge_slope[e])));
        const __m128 lo_e = _mm_min_ps(_mm_min_ps(_mm_set1_ps(flat_min[e]), xc), x_min);
        const __m128 hi_e = _mm_max_ps(_mm_max_ps(_mm_set1_ps(flat_max[e]), xc), x_max);
        x_min = _mm_or_ps(_mm_and_ps(meets, lo_e), _mm_andnot_ps(meets, x_min));
        x_max = _mm_or_ps(_mm_and_ps(meets, hi_e), _mm_andnot_ps(meets, x_max));
      }
      const __m128i none = _mm_castps_si128(_mm_cmpnle_ps(x_min, x_max));  // (also NaN)
      const __m128i x0 = floor4(_mm_sub_ps(x_min, half));
      const __m128i x1 = _mm_add_epi32(floor4(_mm_sub_ps(x_max, half)), _mm_set1_epi32(2));
      _mm_store_si128(reinterpret_cast<__m128i*>(row_x0 + (y - lo.y)), _mm_andnot_si128(none, x0));
      _mm_store_si128(reinterpret_cast<__m128i*>(row_x1 + (y - lo.y)), _mm_andnot_si128(none, x1));
    }
  }
  for (int y = lo.y; y < hi.y; ++y) {
    const float yc = float(y + s.origin.y) + 0.5f;
    const int x0 = std::max(lo.x, row_x0[y - lo.y] - s.origin.x);
    const int x1 = std::min(hi.x, row_x1[y - lo.y] - s.origin.x);
    if (x0 >= x1) continue;
    // Room for a whole row (at most the area's width) before it is walked.
    if (frags.n + (x1 - x0) > Fragments::kMax) flush();
    const glm::vec4 row = col_y * yc + col_w;
    const glm::vec3 hr(row);
    const size_t line = size_t(y - im.min.y) * size_t(im.stride) - size_t(im.min.x);
    if (kOrtho) {
      for (int x = x0; x < x1; ++x) {
        // plane_point(): along -z through the pixel.
        const glm::vec4 h = col_x * (float(x + s.origin.x) + 0.5f) + row;
        const glm::vec3 on_ray = glm::vec3(h) / h.w;
        const glm::vec3 p(on_ray.x, on_ray.y, on_ray.z + glm::dot(sp.center - on_ray, sp.normal) / sp.normal.z);
        if (!(std::abs(p.z) < 3.0e38f)) continue;  // the plane seen edge on
        const glm::vec3 rel = p - sp.center;
        const float u = glm::dot(rel, sp.u_axis) + 0.5f, v = glm::dot(rel, sp.v_axis) + 0.5f;
        if (!(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f)) continue;  // off the quad
        const float depth = std::clamp(-p.z, near_d, far_d), surface = im.surface[line + size_t(x)];
        // Orthographic rays are parallel: the move toward the camera is the offset itself.
        const bool nearer = depth < surface;
        const bool keep = kDepth ? nearer : (depth <= surface || depth - sp.offset <= surface);
        const int k = frags.n;
        frags.q[k] = uint32_t(line + size_t(x));
        frags.u[k] = u;
        frags.v[k] = v;
        frags.depth[k] = depth;
        frags.length[k] = 0.0f;
        frags.nearer[k] = nearer;
        frags.n += keep;
      }
      if (P != Pass::kBlend) blocks.touch(y, x0, x1);
      continue;
    }
    const float d0 = glm::dot(hr, sp.normal), u0 = glm::dot(hr, sp.u_axis), v0 = glm::dot(hr, sp.v_axis);
    const RowLanes r{plane, d0, dx, u0, ux, v0, vx, cu, cv, near_d, far_d, sp.offset, hx, hr,
                     s.origin.x, im.surface + line, line};
    bool nearer;
    if constexpr (kAvx2) nearer = row_avx2<P>(r, x0, x1, frags);
    else nearer = row_lanes<P>(r, x0, x1, frags);
    if (P != Pass::kBlend && nearer) blocks.touch(y, x0, x1);
  }
  flush();
  if (P == Pass::kBoth && out->count > begin) out->runs.push_back({place, uint32_t(begin), uint32_t(out->count)});
}
template <Pass P, bool kOrtho>
__attribute__((target("avx2"), flatten)) void rasterize_avx2(uint32_t place, const Splat& sp, const Settings& s,
                                                             const Rect& area, const Images& im, BlockDepths& blocks,
                                                             Candidates* out) {
  rasterize_splat<P, kOrtho, true>(place, sp, s, area, im, blocks, out);
}
#pragma GCC diagnostic pop
template <Pass P, bool kOrtho>
void rasterize(uint32_t place, const Splat& sp, const Settings& s, const Rect& area, const Images& im,
               BlockDepths& blocks, Candidates* out) {
  if (s.avx2) return rasterize_avx2<P, kOrtho>(place, sp, s, area, im, blocks, out);
  rasterize_splat<P, kOrtho, false>(place, sp, s, area, im, blocks, out);
}

// blend_candidates()'s test of one run (one splat's candidates, each on
// its own pixel) on AVX2 lanes, the same float operations; the kept ones
// blend one by one.
__attribute__((target("avx2"))) void blend_run_avx2(const Splat& sp, const Settings& s, const Images& im,
                                                    const Candidates& c, uint32_t begin, uint32_t end) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 offset = _mm256_set1_ps(sp.offset);
  const __m256 ortho = _mm256_castsi256_ps(_mm256_set1_epi32(s.ortho ? -1 : 0));
  const __m128 rgb1 = _mm_setr_ps(sp.rgb.r, sp.rgb.g, sp.rgb.b, 1.0f);
  // (Locals: the blend's stores must not make the compiler fetch them again.)
  const uint32_t* const qs = c.q.get();
  const float *const depths = c.depth.get(), *const lengths = c.length.get(), *const a1 = c.a1.get(), *const a2 = c.a2.get();
  for (uint32_t i = begin; i < end; i += 8) {
    const __m256 live = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(int32_t(end - i)), lane));
    const __m256i q = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(qs + i));
    const __m256 depth = _mm256_loadu_ps(depths + i), length = _mm256_loadu_ps(lengths + i);
    const __m256 surface = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), im.surface, q, live, 4);
    const __m256 behind = _mm256_sub_ps(depth, surface), reach = _mm256_mul_ps(depth, offset);
    const __m256 near = _mm256_or_ps(ortho, _mm256_cmp_ps(_mm256_mul_ps(_mm256_mul_ps(length, behind), behind),
                                                          _mm256_mul_ps(reach, reach), _CMP_LE_OQ));
    const __m256 keep = _mm256_or_ps(_mm256_cmp_ps(depth, surface, _CMP_LE_OQ),
                                     _mm256_and_ps(_mm256_cmp_ps(_mm256_sub_ps(depth, offset), surface, _CMP_LE_OQ), near));
    const int kept = _mm256_movemask_ps(_mm256_and_ps(keep, live));
    if (sp.two) {
      for (int m = kept; m != 0; m &= m - 1) {
        const uint32_t k = i + uint32_t(__builtin_ctz(unsigned(m)));
        blend(sp, s, im, qs[k], a1[k], a2[k]);
      }
      continue;
    }
    // blend() of one layer: the colour sum's four channels at once (a times
    // 1 is a: the same sums).
    for (int m = kept; m != 0; m &= m - 1) {
      const uint32_t k = i + uint32_t(__builtin_ctz(unsigned(m)));
      const float a = a1[k];
      if (!(a >= kBrushCut)) continue;
      float* acc = im.accum + 4 * size_t(qs[k]);
      _mm_storeu_ps(acc, _mm_add_ps(_mm_loadu_ps(acc), _mm_mul_ps(rgb1, _mm_set1_ps(a))));
      im.reveal[qs[k]] *= 1.0f - a;
    }
  }
}

// The blend of a bin's candidates against its final surface, splats in
// point order (the bin's list of n): the blend pass's tests and float
// operations, so its bytes.
void blend_candidates(const std::vector<Splat>& splats, const uint32_t* list, size_t n, const Settings& s,
                      const Images& im, Candidates& c) {
  std::vector<uint32_t>& run_at = c.run_at;  // by place, past the runs: none
  run_at.assign(n, uint32_t(c.runs.size()));
  for (size_t r = 0; r < c.runs.size(); ++r) run_at[c.runs[r].place] = uint32_t(r);
  for (size_t place = 0; place < n; ++place) {
    if (run_at[place] == c.runs.size()) continue;
    const Candidates::Run& run = c.runs[run_at[place]];
    const Splat& sp = splats[list[place]];
    if (s.avx2) {
      blend_run_avx2(sp, s, im, c, run.begin, run.end);
      continue;
    }
    for (uint32_t i = run.begin; i < run.end; ++i) {
      const float depth = c.depth[i], surface = im.surface[c.q[i]];
      // (Without branches but the last: their outcomes are a coin's toss.)
      const float behind = depth - surface, reach = depth * sp.offset;
      const bool keep = (depth <= surface) |
                        ((depth - sp.offset <= surface) & (s.ortho | (c.length[i] * behind * behind <= reach * reach)));
      if (keep) blend(sp, s, im, c.q[i], c.a1[i], c.a2[i]);
    }
  }
}

// A TBB worker's scratch for the bins it draws: their keys in list and
// depth order, and the fragments a bin's depth pass keeps for its blend.
struct BinScratch {
  std::vector<uint64_t> near, sort_scratch;
  std::vector<SplatKey> listed, sorted;
  Candidates candidates;
  size_t bytes() const {
    return held_bytes(near) + held_bytes(sort_scratch) + held_bytes(listed) + held_bytes(sorted) +
           5 * (Candidates::kMax + 8) * sizeof(float) + held_bytes(candidates.runs) +
           held_bytes(candidates.run_at);
  }
};

// The host images of the last frames and the workers' scratch, kept by the
// renderer (HostScratch) so a frame does not page-fault them in anew
// (bounded by the largest clip, a tile's region at most).
struct HostImages {
  std::vector<float> surface, accum, reveal, sums, color;
  std::vector<Splat> splats;  // a batch's (at most kBatch)
  std::vector<SplatKey> keys;  // theirs
  tbb::enumerable_thread_specific<BinScratch> bins;
  size_t bytes() const {
    size_t n = held_bytes(surface) + held_bytes(accum) + held_bytes(reveal) + held_bytes(sums) +
               held_bytes(color) + held_bytes(splats) + held_bytes(keys);
    for (const BinScratch& b : bins) n += b.bytes();
    return n;
  }
};
HostImages& host_images(HostScratch& host, size_t pixels) {
  HostImages& images = host.get<HostImages>();
  if (images.surface.size() < pixels + 8) {
    images.surface.resize(pixels + 8);  // slack for the row loop's last lanes
    images.accum.resize(4 * pixels);
    images.reveal.resize(pixels);
    images.sums.resize(4 * pixels);
    images.color.resize(4 * pixels);
  }
  return images;
}

// The brush's falloff as kPieces polynomials over t (or sqrt(t)) of the
// lowest degree up to kDegree that stays within kPieceError of
// exp(-q^lambda / 2) on a fine grid, as the runtime evaluates them (floats,
// Horner), interpolated at each piece's Chebyshev nodes; steep shapes
// (lambda < 1 at 0, very high lambda) keep the table. Eight lanes look a
// piece's coefficients up in registers, where the table takes two gathers.
constexpr double kPieceError = 1e-5;
void fit_pieces(Settings& s, double lambda) {
  auto exact = [&](double t) { return std::exp(-0.5 * std::pow(double(s.reach) * (s.sqrt_index ? t * t : t), lambda)); };
  for (int degree = 3; degree <= kDegree; ++degree) {
    Eigen::MatrixXd vandermonde(degree + 1, degree + 1);
    Eigen::VectorXd values(degree + 1);
    for (int i = 0; i < kPieces; ++i) {
      for (int k = 0; k <= degree; ++k) {
        const double f = 0.5 - 0.5 * std::cos((k + 0.5) * M_PI / (degree + 1));
        for (int d = 0; d <= degree; ++d) vandermonde(k, d) = std::pow(f, d);
        values(k) = exact((i + f) / kPieces);
      }
      const Eigen::VectorXd c = vandermonde.colPivHouseholderQr().solve(values);
      for (int d = 0; d <= kDegree; ++d) s.poly[d][i] = d <= degree ? float(c(d)) : 0.0f;
    }
    s.pieces = true;
    s.degree = degree;
    double worst = 0.0;
    for (int j = 0; j <= 64 * kPieces; ++j) {
      const double t = double(j) / (64 * kPieces);
      worst = std::max(worst, std::abs(double(falloff(s, float(s.sqrt_index ? t * t : t) * s.reach)) - exact(t)));
    }
    if (worst <= kPieceError) return;
  }
  s.pieces = false;
}

Settings settings(const MarkContext& ctx, const ParamValues& p) {
  const Camera& cam = *ctx.camera;
  Settings s;
  s.avx2 = kCpuHasAvx2 && !ctx.native.scalar_lanes;
  const glm::ivec2 frame = frame_size(ctx.targets);
  s.frame = glm::vec2(frame);
  s.origin = ctx.targets.origin;
  s.clip = ctx.clip;
  s.near = float(cam.clip_start);
  s.far = float(cam.clip_end);
  s.ortho = cam.orthographic;
  s.px_per_unit = float(cam.pixels_per_unit(1.0, frame.y));
  s.projection = glm::mat4(cam.projection);
  // As brush_splats.cpp's u_view_from_pixel: composed in double.
  glm::dmat4 ndc_from_pixel(0.0);
  ndc_from_pixel[0][0] = 2.0 / double(frame.x);
  ndc_from_pixel[1][1] = 2.0 / double(frame.y);
  ndc_from_pixel[3] = glm::dvec4(-1.0, -1.0, -1.0, 1.0);
  s.view_from_pixel = glm::mat4(glm::inverse(cam.projection) * ndc_from_pixel);
  s.resolution_size = p.get_enum_name("size_mode") == "resolution";
  s.user_eps = s.resolution_size && p.get_enum_name("epsilon_mode") == "user";
  s.epsilon = s.resolution_size ? float(p.get_float("epsilon")) : 0.0f;
  s.size_scale = float(p.get_float("size_scale"));
  s.world_radius = s.resolution_size ? 0.0f : float(p.get_float("world_radius"));
  s.max_radius_px = float(p.get_float("max_radius"));
  s.tangent_frame = p.get_enum("tangent_frame");
  s.angle = float(glm::radians(p.get_float("brush_angle")));
  s.jitter = float(glm::radians(p.get_float("angle_jitter")));
  s.seed = uint32_t(p.get_int("seed"));
  s.two_layers = p.get_enum_name("layers") == "two";
  s.clusters = p.get_bool("clusters");
  s.small_cluster = s.clusters ? float(p.get_int("small_cluster")) : 0.0f;
  s.elongation_gain = float(p.get_float("elongation_stretch"));
  s.max_stretch = float(p.get_float("max_stretch"));
  s.depth_tolerance = float(p.get_float("depth_tolerance"));
  s.gaussians = p.get_int("gaussians");
  const int rows = (s.gaussians + 2) / 3;
  const float dev = float(p.get_float("dev"));
  int k = 0;
  for (int row = 0; row < 3; ++row) {
    const int cols = std::clamp(s.gaussians - row * 3, 0, 3);
    for (int col = 0; col < cols; ++col, ++k) {
      s.cx[k] = 0.5f + (float(col) - 0.5f * float(cols - 1)) * dev;
      s.cy[k] = 0.5f + (float(row) - 0.5f * float(rows - 1)) * dev;
      s.column[k] = col;
    }
  }
  s.amplitude = float(p.get_float("amplitude"));
  s.inv_sx = 1.0f / float(p.get_float("sigma_x"));
  s.inv_sy = 1.0f / float(p.get_float("sigma_y"));
  s.reach = float(brush_reach(p));
  s.inv_reach = 1.0f / s.reach;
  s.layer_scale = float(p.get_float("layer_scale"));
  const float layer_angle = float(glm::radians(p.get_float("layer_angle")));
  s.layer_cos = std::cos(layer_angle);
  s.layer_sin = std::sin(layer_angle);
  s.layer_tint = float(p.get_float("layer_tint"));
  const double lambda = p.get_float("lambda");
  s.table.resize(kTable + 2);
  s.sqrt_index = lambda < 1.0;
  for (int i = 0; i <= kTable; ++i) {
    const double t = double(i) / kTable;
    s.table[size_t(i)] = float(std::exp(-0.5 * std::pow(double(s.reach) * (s.sqrt_index ? t * t : t), lambda)));
  }
  s.table[kTable + 1] = s.table[kTable];
  fit_pieces(s, lambda);
  return s;
}

// The blur's numbers (brush_blur.comp): Gaussian taps, depth occlusion.
struct BlurTaps {
  int radius = 0;
  float tolerance = 0.0f;
  std::vector<float> weight;  // 2 radius + 1
};

// A neighbour at depth dq counts for a pixel at depth d (not infinite, not
// beyond the tolerance; as brush_blur.comp).
bool blur_counts(float dq, float d, float tolerance) {
  return !(std::isinf(dq) || std::abs(dq - d) > tolerance * d);
}

// !std::isinf(v) on eight lanes (NaN counts as not infinite, as there).
__attribute__((target("avx2"), always_inline)) inline __m256 not_inf8(__m256 v) {
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  return _mm256_cmp_ps(_mm256_and_ps(v, magnitude), _mm256_set1_ps(kInf), _CMP_NEQ_UQ);
}
// Eight pixels' neighbour test on AVX2 lanes: blur_counts().
__attribute__((target("avx2"), always_inline)) inline __m256 blur_counts8(__m256 dq, __m256 d, __m256 tolerance) {
  const __m256 magnitude = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  const __m256 beyond = _mm256_cmp_ps(_mm256_and_ps(_mm256_sub_ps(dq, d), magnitude), _mm256_mul_ps(tolerance, d),
                                      _CMP_GT_OQ);
  return _mm256_andnot_ps(beyond, not_inf8(dq));
}

// The horizontal pass for pixels [x0, x0 + 8) of a row, none within the
// radius of the row's ends: rgb * w and w summed per pixel, tap by tap (the
// scalar pass's order), into the planar sums. The interleaved colour is
// read four registers at a time and transposed; its lanes hold the pixels
// in the order 0 2 4 6 1 3 5 7, and the depths are read in that order too.
__attribute__((target("avx2"))) void blur_x_avx2(const BlurTaps& taps, const float* color, const float* depth, int x0,
                                                 float* const* sums) {
  const __m256i order = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7), back = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
  const __m256 d = _mm256_permutevar8x32_ps(_mm256_loadu_ps(depth + x0), order);
  const __m256 tolerance = _mm256_set1_ps(taps.tolerance);
  const __m256 live = not_inf8(d);
  __m256 sum[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
  for (int k = -taps.radius; k <= taps.radius; ++k) {
    const int x = x0 + k;
    const __m256 counts = blur_counts8(_mm256_permutevar8x32_ps(_mm256_loadu_ps(depth + x), order), d, tolerance);
    const float* c = color + 4 * x;
    const __m256 v0 = _mm256_loadu_ps(c), v1 = _mm256_loadu_ps(c + 8), v2 = _mm256_loadu_ps(c + 16),
                 v3 = _mm256_loadu_ps(c + 24);
    const __m256 t0 = _mm256_unpacklo_ps(v0, v1), t1 = _mm256_unpackhi_ps(v0, v1);
    const __m256 t2 = _mm256_unpacklo_ps(v2, v3), t3 = _mm256_unpackhi_ps(v2, v3);
    const __m256 channel[3] = {_mm256_shuffle_ps(t0, t2, 0x44), _mm256_shuffle_ps(t0, t2, 0xee),
                               _mm256_shuffle_ps(t1, t3, 0x44)};
    const __m256 w = _mm256_mul_ps(_mm256_set1_ps(taps.weight[size_t(k + taps.radius)]), _mm256_shuffle_ps(t1, t3, 0xee));
    for (int ch = 0; ch < 3; ++ch) sum[ch] = _mm256_add_ps(sum[ch], _mm256_and_ps(counts, _mm256_mul_ps(channel[ch], w)));
    sum[3] = _mm256_add_ps(sum[3], _mm256_and_ps(counts, w));
  }
  for (int ch = 0; ch < 4; ++ch)
    _mm256_storeu_ps(sums[ch] + x0, _mm256_permutevar8x32_ps(_mm256_and_ps(live, sum[ch]), back));
}

// The vertical pass for pixels [x0, x0 + 8) of row y (frame of `width` x
// `height`): the planar sums of the rows within the radius, then each
// covered pixel's rgb as their ratio (alpha unchanged), in place.
__attribute__((target("avx2"))) void blur_y_avx2(const BlurTaps& taps, float* color, const float* depth,
                                                 const float* const* sums, int x0, int y, int width, int height) {
  const size_t i = size_t(y) * size_t(width) + size_t(x0);
  const __m256 d = _mm256_loadu_ps(depth + i);
  const __m256 tolerance = _mm256_set1_ps(taps.tolerance);
  __m256 sum[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
  for (int k = -taps.radius; k <= taps.radius; ++k) {
    const size_t q = size_t(std::clamp(y + k, 0, height - 1)) * size_t(width) + size_t(x0);
    const __m256 counts = blur_counts8(_mm256_loadu_ps(depth + q), d, tolerance);
    const __m256 w = _mm256_set1_ps(taps.weight[size_t(k + taps.radius)]);
    for (int ch = 0; ch < 4; ++ch)
      sum[ch] = _mm256_add_ps(sum[ch], _mm256_and_ps(counts, _mm256_mul_ps(w, _mm256_loadu_ps(sums[ch] + q))));
  }
  const __m256 live = not_inf8(d);
  const int mask = _mm256_movemask_ps(_mm256_and_ps(live, _mm256_cmp_ps(sum[3], _mm256_setzero_ps(), _CMP_GT_OQ)));
  if (mask == 0) return;
  alignas(32) float ratio[3][8];
  for (int ch = 0; ch < 3; ++ch) _mm256_store_ps(ratio[ch], _mm256_div_ps(sum[ch], sum[3]));
  for (int m = mask; m != 0; m &= m - 1) {
    const int p = __builtin_ctz(unsigned(m));
    float* c = color + 4 * (i + size_t(p));
    for (int ch = 0; ch < 3; ++ch) c[ch] = ratio[ch][p];
  }
}

// brush_blur.comp over the clip: along x into `sums` (planar: one plane per
// channel, rgb * w and w), then along y back into `color` (each channel's
// float operations as the shader's, in its order; eight pixels at a time on
// AVX2 lanes where the CPU has them, the same operations). Only the covered
// pixels (each row's span of them) are read and written: the others stay as
// they are (transparent), and no covered pixel reads their sums.
void blur(const Settings& s, const ParamValues& p, float* color, const float* depth,
          const std::vector<glm::ivec2>& row_span, float* sums) {
  BlurTaps taps;
  taps.radius = p.get_int("blur_radius");
  const float sigma = std::max(0.5f, 0.5f * float(taps.radius));
  taps.tolerance = float(p.get_float("blur_depth_tolerance"));
  const int radius = taps.radius;
  taps.weight.resize(size_t(2 * radius + 1));
  for (int k = -radius; k <= radius; ++k) taps.weight[size_t(k + radius)] = std::exp(-0.5f * float(k * k) / (sigma * sigma));
  const glm::ivec2 size = s.clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  float* const planes[4] = {sums, sums + pixels, sums + 2 * pixels, sums + 3 * pixels};
  auto at = [&](int x, int y) { return size_t(y) * size_t(size.x) + size_t(x); };
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const glm::ivec2 span = row_span[size_t(y)];
      const float* color_row = color + 4 * at(0, y);
      const float* depth_row = depth + at(0, y);
      for (int x = span.x; x <= span.y;) {
        // Eight at a time where no tap reaches past the row's ends.
        if (s.avx2 && x + 8 <= span.y + 1 && x - radius >= 0 && x + 7 + radius <= size.x - 1) {
          float* const row_planes[4] = {planes[0] + at(0, y), planes[1] + at(0, y), planes[2] + at(0, y),
                                        planes[3] + at(0, y)};
          blur_x_avx2(taps, color_row, depth_row, x, row_planes);
          x += 8;
          continue;
        }
        const float d = depth_row[x];
        float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        if (!std::isinf(d)) {
          for (int k = -radius; k <= radius; ++k) {
            const int q = std::clamp(x + k, 0, size.x - 1);
            if (!blur_counts(depth_row[q], d, taps.tolerance)) continue;
            const float w = taps.weight[size_t(k + radius)] * color_row[4 * q + 3];
            for (int ch = 0; ch < 3; ++ch) sum[ch] += color_row[4 * q + ch] * w;
            sum[3] += w;
          }
        }
        for (int ch = 0; ch < 4; ++ch) planes[ch][at(x, y)] = sum[ch];
        ++x;
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const glm::ivec2 span = row_span[size_t(y)];
      for (int x = span.x; x <= span.y;) {
        if (s.avx2 && x + 8 <= span.y + 1) {
          blur_y_avx2(taps, color, depth, planes, x, y, size.x, size.y);
          x += 8;
          continue;
        }
        const int px = x++;
        const size_t i = at(px, y);
        const float d = depth[i];
        float* c = &color[4 * i];  // (read before written: the pixel's own)
        if (std::isinf(d)) continue;
        float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int k = -radius; k <= radius; ++k) {
          const size_t q = at(px, std::clamp(y + k, 0, size.y - 1));
          if (!blur_counts(depth[q], d, taps.tolerance)) continue;
          const float w = taps.weight[size_t(k + radius)];
          for (int ch = 0; ch < 4; ++ch) sum[ch] += w * planes[ch][q];
        }
        for (int ch = 0; ch < 3; ++ch) c[ch] = sum[3] > 0.0f ? sum[ch] / sum[3] : c[ch];
      }
    }
  });
}

#undef POINTNPR_AVX2_INLINE
}  // namespace

void draw_brush_splats_native(const MarkContext& ctx, const ParamValues& p) {
  const Rect clip = ctx.clip;
  if (clip.empty()) {
    if (ctx.coverage) *ctx.coverage = Rect{};
    return;
  }
  const Settings s = settings(ctx, p);
  const int k = p.get_int("resolution_neighbors");
  const int normal_k = p.get_int("normal_neighbors");
  const bool radius_normals = p.get_enum_name("normals") == "radius_3r";
  const ColorSource source = ColorSource(p.get_enum("color_source"));
  const glm::vec4 constant = p.get_color("color");

  // What the point frames follow (the parameters that reach point_frame()).
  std::string frames_key;
  {
    auto add = [&frames_key](auto v) { frames_key += std::to_string(v) + ' '; };
    add(normal_k), add(radius_normals), add(s.resolution_size), add(k), add(s.user_eps);
    for (float f : {s.epsilon, s.world_radius, s.size_scale, s.angle, s.jitter, s.small_cluster, s.elongation_gain,
                    s.max_stretch})
      add(std::bit_cast<uint32_t>(f));
    add(s.tangent_frame), add(s.seed), add(s.two_layers), add(s.clusters), add(p.get_int("cluster_neighbors"));
  }
  // Host data of every chunk, held while drawing. Point frames are kept for
  // clouds of at most kKeptFramesMax points (NativeLimits::kept_frames_max,
  // tests: fewer); larger ones make them per splat, each frame.
  const uint64_t kept_frames_max = NativeLimits::lowered(ctx.native.kept_frames_max, kKeptFramesMax);
  int clouds_with_kept_frames = 0;
  std::vector<Chunk> chunks(ctx.chunks.size());
  std::vector<std::shared_ptr<const void>> held;
  const PointCloud* last = nullptr;
  Chunk proto;
  for (size_t i = 0; i < ctx.chunks.size(); ++i) {
    const VisibleChunk& v = ctx.chunks[i];
    std::shared_ptr<const PointCloud> cloud = v.gpu->source.lock();
    if (!cloud) throw GLError("brush_splats: a visible chunk's cloud is gone");
    if (cloud.get() != last) {
      last = cloud.get();
      // Their inputs (the caches the GPU cloud's uploads come from).
      auto frame_inputs = [&](std::vector<std::shared_ptr<const void>>& hold) {
        geometry::Analysis& analysis = cloud->analysis();
        FrameInputs in;
        in.ids = cloud->point_index().data();
        if (v.gpu->own_normals) {
          in.normals = cloud->normals().data();
        } else {
          geometry::NormalOptions o{normal_k, geometry::Orientation::Consistent, {}};
          if (radius_normals) o.radius_factor = 3.0;
          auto normals = analysis.normals(o);
          in.normals = normals->data();
          hold.push_back(normals);
        }
        if (s.resolution_size) {
          auto resolution = analysis.local_resolution(k);
          in.r = resolution->r.data();
          in.eps = resolution->eps.data();
          hold.push_back(resolution);
        }
        if (s.tangent_frame == 3) {
          auto pca = analysis.pca(normal_k);
          auto axes = std::make_shared<const std::vector<glm::vec3>>(analysis.points().to_original(pca->major));
          in.axes = axes->data();
          hold.push_back(axes);
        }
        if (s.clusters) {
          auto shapes = analysis.cluster_shapes(p.get_int("cluster_neighbors"));
          in.shapes = shapes.get();
          hold.push_back(shapes);
        }
        return in;
      };
      proto = Chunk{};
      if (cloud->size() <= kept_frames_max) {
        PointFrames& kept = v.gpu->host_slot<PointFrames>("brush_splats point frames");
        const std::string cloud_key = frames_key + std::to_string(v.gpu->own_normals);
        if (kept.key != cloud_key || kept.frames.size() != cloud->size()) {
          kept.key.clear();  // (stale until made)
          std::vector<std::shared_ptr<const void>> inputs;
          const FrameInputs in = frame_inputs(inputs);
          kept.frames.resize(cloud->size());
          PointFrame* frames = kept.frames.data();
          tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(cloud->size()), kGrain),
                            [&](const tbb::blocked_range<uint32_t>& r) {
                              for (uint32_t j = r.begin(); j < r.end(); ++j) frames[j] = point_frame(in, s, j);
                            });
          kept.key = cloud_key;
        }
        proto.frames = kept.frames.data();
        ++clouds_with_kept_frames;
      } else {
        proto.in = frame_inputs(held);
      }
      proto.positions = cloud->local_positions().data();
      proto.colors = host_colors(*v.gpu, *cloud, source, constant);
      held.push_back(cloud);
    }
    Chunk& c = chunks[i];
    c = proto;
    c.order = draws_queue(v, p) ? v.gpu->host_queue_order().data() + v.chunk->first : nullptr;
    c.first = v.chunk->first;
    c.count = queue_count(v, p);
    c.view = v.view_from_chunk;
  }
  uint64_t drawn = 0;
  for (const Chunk& c : chunks) drawn += c.count;

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const glm::ivec2 size = clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  HostImages& host = host_images(*ctx.host, pixels);
  const Images im{host.surface.data(), host.accum.data(), host.reveal.data(), size.x, clip.min};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(im.surface + r.begin(), im.surface + r.end(), kInf);
    std::fill(im.accum + 4 * r.begin(), im.accum + 4 * r.end(), 0.0f);
    std::fill(im.reveal + r.begin(), im.reveal + r.end(), 1.0f);
  });

  // Batches of whole chunks (a chunk larger than a batch is one), set up
  // in parallel and kept in point order; with one batch the blend pass
  // reuses the depth pass's splats.
  struct Item {
    uint32_t chunk, begin, end;
  };
  // NativeLimits::batch_splats (tests): fewer splats a batch, so that several
  // run the passes apart.
  const uint64_t batch_splats = NativeLimits::lowered(ctx.native.batch_splats, kBatch);
  std::vector<std::pair<size_t, size_t>> batches;
  for (size_t b = 0; b < chunks.size();) {
    size_t e = b;
    uint64_t used = 0;
    while (e < chunks.size() && (e == b || used + chunks[e].count <= batch_splats)) used += chunks[e++].count;
    batches.push_back({b, e});
    b = e;
  }
  std::vector<Splat>& splats = host.splats;
  std::vector<SplatKey>& keys = host.keys;
  double setup_ms = 0.0;
  auto set_up = [&](size_t b, size_t e) {
    const auto ts = Clock::now();
    std::vector<Item> items;
    for (size_t i = b; i < e; ++i)
      for (uint32_t j = 0; j < chunks[i].count; j += kGrain)
        items.push_back({uint32_t(i), j, std::min(chunks[i].count, j + kGrain)});
    // Each point's slot in point order; one not drawn covers nothing.
    std::vector<size_t> slot(items.size() + 1, 0);
    for (size_t n = 0; n < items.size(); ++n) slot[n + 1] = slot[n] + (items[n].end - items[n].begin);
    splats.resize(slot.back());
    keys.resize(slot.back());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t n = r.begin(); n < r.end(); ++n) {
        const Item& it = items[n];
        const Chunk& c = chunks[it.chunk];
        Splat* out = splats.data() + slot[n];
        if (s.avx2) {
          for (uint32_t j = it.begin; j < it.end; j += 8, out += 8) {
            const int lanes = int(std::min(8u, it.end - j));
            uint32_t index[8];
            for (int i = 0; i < lanes; ++i) index[i] = c.first + (c.order ? c.order[j + uint32_t(i)] : j + uint32_t(i));
            setup_avx2(c, s, index, lanes, out);
          }
        } else {
          for (uint32_t j = it.begin; j < it.end; ++j, ++out)
            if (!setup(c, s, c.first + (c.order ? c.order[j] : j), *out)) out->lo = out->hi = glm::ivec2(0);
        }
      }
      for (size_t i = slot[r.begin()]; i < slot[r.end()]; ++i) keys[i] = SplatKey(splats[i]);
    });
    setup_ms += std::chrono::duration<double, std::milli>(Clock::now() - ts).count();
  };
  std::atomic<int> bins_blended_apart{0};  // over Candidates::kMax
  // One pass P over the batch in `splats`, bin by bin.
  auto pass = [&](auto which) {
    constexpr Pass P = decltype(which)::value;
    auto bounds = [&](size_t i, glm::ivec2& lo, glm::ivec2& hi) {
      lo = keys[i].lo;
      hi = keys[i].hi;
      return lo.x < hi.x && lo.y < hi.y;
    };
    auto bin = [&](const Rect& area, const uint32_t* list, size_t n) {
      BlockDepths blocks;
      blocks.area = area;
      blocks.im = &im;
      // The blend pass: in point order, splats behind the surface by more
      // than their offset dropped.
      auto blend_pass = [&] {
        blocks.rescan_all();
        for (size_t j = 0; j < n; ++j) {
          const SplatKey& key = keys[list[j]];
          if (key.near - key.offset > blocks.under(key.lo, key.hi)) continue;
          const Splat& sp = splats[list[j]];
          if (s.ortho) rasterize<Pass::kBlend, true>(list[j], sp, s, area, im, blocks, nullptr);
          else rasterize<Pass::kBlend, false>(list[j], sp, s, area, im, blocks, nullptr);
        }
      };
      if (P == Pass::kBlend) return blend_pass();
      // The nearest depth does not depend on the order: near splats first
      // leave most later fragments behind it, unshaded. Sorted as keys of
      // the nearest depth (positive, beyond the near plane: its bits sort
      // as it) over the place in the list (in point order), read in point
      // order, not through the splats.
      BinScratch& scratch = host.bins.local();
      std::vector<uint64_t>& near = scratch.near;
      std::vector<uint64_t>& sort_scratch = scratch.sort_scratch;
      std::vector<SplatKey>& listed = scratch.listed;  // the bin's keys in list order,
      std::vector<SplatKey>& sorted = scratch.sorted;  // then in depth order
      near.resize(n);
      listed.resize(n);
      float max_offset = 0.0f;
      for (size_t j = 0; j < n; ++j) {
        const SplatKey& key = listed[j] = keys[list[j]];
        near[j] = uint64_t(std::bit_cast<uint32_t>(key.near)) << 32 | j;
        max_offset = std::max(max_offset, key.offset);
      }
      stable_sort_by_high_words(near, sort_scratch);  // (ties: in list order, as std::sort)
      // Their keys in that order, gathered at once (from the bin's copy):
      // the loop below reads them in turn.
      sorted.resize(n);
      for (size_t j = 0; j < n; ++j) sorted[j] = listed[uint32_t(near[j])];
      Candidates& candidates = scratch.candidates;
      candidates.clear();
      // Once the splats since cover the bin's area (so the scan costs at
      // most what they did), the bin's farthest surface: every later splat
      // (sorted) behind it (by more than the offsets, kBoth) is dropped.
      float bin_far = kInf;
      const size_t bin_area = size_t(area.size().x) * size_t(area.size().y);
      size_t painted = 0;
      for (size_t j = 0; j < n; ++j) {
        // In depth order the splats are far apart in memory: fetched ahead.
        if (j + 8 < n) {
          const char* ahead = reinterpret_cast<const char*>(&splats[list[uint32_t(near[j + 8])]]);
          for (size_t line = 0; line < sizeof(Splat); line += 64) __builtin_prefetch(ahead + line);
        }
        const uint32_t place = uint32_t(near[j]), index = list[place];
        const SplatKey& key = sorted[j];
        const glm::ivec2 box = glm::min(key.hi, area.max) - glm::max(key.lo, area.min);
        painted += size_t(std::max(box.x, 0)) * size_t(std::max(box.y, 0));
        if (painted >= bin_area) {
          painted = 0;
          bin_far = blocks.under(area.min, area.max);
        }
        // Behind the blocks' bound, or (narrow boxes) behind the surface under the box.
        const bool narrow = box.x <= 8;
        if (P == Pass::kDepth) {
          if (key.near >= bin_far) break;
          if (key.near >= blocks.under(key.lo, key.hi)) continue;
          if (narrow && key.near >= blocks.under_exactly(key.lo, key.hi)) continue;
        } else {
          if (key.near - max_offset > bin_far) break;
          if (key.near - key.offset > blocks.under(key.lo, key.hi)) continue;
          if (narrow && key.near - key.offset > blocks.under_exactly(key.lo, key.hi)) continue;
        }
        const Splat& sp = splats[index];
        if (s.ortho) rasterize<P, true>(place, sp, s, area, im, blocks, &candidates);
        else rasterize<P, false>(place, sp, s, area, im, blocks, &candidates);
      }
      if (P == Pass::kBoth) {
        if (!candidates.full) return blend_candidates(splats, list, n, s, im, candidates);
        ++bins_blended_apart;
        blend_pass();
      }
    };
    // Bins of kBinSide (BlockDepths, the rows' arrays): wider ones (past
    // 16384 bins, frames over 67M pixels; NativeLimits::max_bins, tests:
    // past that many) are cut, their lists filtered.
    const size_t max_bins = NativeLimits::lowered(ctx.native.max_bins, 16384);
    for_each_bin_in_order(splats.size(), clip, bounds, [&](const Rect& area, const uint32_t* list, size_t n) {
      if (area.size().x <= kBinSide && area.size().y <= kBinSide) return bin(area, list, n);
      std::vector<uint32_t> part;
      for (int y = area.min.y; y < area.max.y; y += kBinSide)
        for (int x = area.min.x; x < area.max.x; x += kBinSide) {
          const Rect cut{{x, y}, glm::min(glm::ivec2(x, y) + kBinSide, area.max)};
          part.clear();
          for (size_t j = 0; j < n; ++j) {
            const SplatKey& key = keys[list[j]];
            if (key.lo.x < cut.max.x && key.hi.x > cut.min.x && key.lo.y < cut.max.y && key.hi.y > cut.min.y) part.push_back(list[j]);
          }
          bin(cut, part.data(), part.size());
        }
    }, kBinSide, max_bins);
  };
  using DepthPass = std::integral_constant<Pass, Pass::kDepth>;
  using BlendPass = std::integral_constant<Pass, Pass::kBlend>;
  using BothPasses = std::integral_constant<Pass, Pass::kBoth>;
  // One batch: each bin's depth pass keeps the fragments its blend needs.
  // Several: every depth pass, then every blend pass (set up again).
  if (batches.size() == 1) {
    set_up(batches[0].first, batches[0].second);
    pass(BothPasses{});
  } else {
    for (const auto& [b, e] : batches) {
      set_up(b, e);
      pass(DepthPass{});
    }
  }
  const auto t1 = Clock::now();
  if (batches.size() > 1) {
    for (const auto& [b, e] : batches) {
      set_up(b, e);
      pass(BlendPass{});
    }
  }
  const auto t2 = Clock::now();

  // Resolve (brush_resolve.comp): straight colour, coverage, the surface's
  // depth (every blended fragment lies on a pixel the depth pass covered).
  float* color = host.color.data();
  float* depth = im.surface;
  std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < size.x; ++x) {
        const size_t q = size_t(y) * size_t(size.x) + size_t(x);
        const float alpha = 1.0f - std::clamp(im.reveal[q], 0.0f, 1.0f);
        const float* acc = im.accum + 4 * q;
        float* c = color + 4 * q;
        if (alpha > 0.0f && acc[3] > 0.0f && !std::isinf(depth[q])) {
          for (int ch = 0; ch < 3; ++ch) c[ch] = std::clamp(acc[ch] / acc[3], 0.0f, 1.0f);
          c[3] = alpha;
          row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, x), x};
        } else {
          std::fill(c, c + 4, 0.0f);
          depth[q] = kInf;
        }
      }
  });
  if (p.get_enum_name("blending") != "none" && p.get_int("blur_radius") > 0)
    blur(s, p, color, depth, row_span, host.sums.data());
  const float* result = color;
  const auto t3 = Clock::now();
  upload_cpu_mark(ctx.targets, clip, result, depth, row_span, ctx.coverage, "brush_splats");
  if (ctx.stats) {
    auto ms = [](Clock::time_point a, Clock::time_point b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    (*ctx.stats)["splats_drawn"] += double(drawn);
    (*ctx.stats)["brush_native_setup_ms"] += setup_ms;
    (*ctx.stats)["brush_native_batches"] += double(batches.size());
    (*ctx.stats)["brush_native_avx2"] = s.avx2 ? 1.0 : 0.0;
    (*ctx.stats)["brush_native_clouds_with_kept_frames"] += double(clouds_with_kept_frames);
    (*ctx.stats)["brush_native_bins_blended_apart"] += double(bins_blended_apart.load());
    (*ctx.stats)["brush_native_depth_ms"] += ms(t0, t1);
    (*ctx.stats)["brush_native_blend_ms"] += ms(t1, t2);
    (*ctx.stats)["brush_native_resolve_ms"] += ms(t2, t3);
    (*ctx.stats)["brush_native_upload_ms"] += ms(t3, Clock::now());
  }
}

}  // namespace pointnpr
