// The hatching mark's native backend: its select and stroke passes
// (hatching_select.comp, hatching_strokes.vert/.frag) on the CPU's threads,
// for software GL devices, compiled from the same kernels
// (hatching_kernels.glsl, hatching_quad.glsl). What is CPU-specific stays
// here: work items of points concatenated in point order (the GL's record
// order), quads binned by screen tiles and blended in that order (the GL's
// blending order), and the depth pass read back from GL.
#include <chrono>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "geometry/analysis.h"
#include "gl/device.h"
#include "marks/hatching/hatching.h"
#include "marks/points/points.h"
#include "render/gpu_cloud.h"
#include "render/native_ink.h"
#include "render/native_raster.h"
#include "render/point_color.h"
#include "render/screen_bins.h"
#include "scene/point_cloud.h"
#include "scene/splat_attributes.h"

namespace pointnpr::hatching {
namespace {

constexpr size_t kBatchStrokes = 1u << 18;   // strokes per batch of quads

// One visible chunk's host data, as the select pass's buffers hold it.
struct HostChunk {
  const glm::vec3* positions = nullptr;  // the cloud's local positions
  const uint32_t* ids = nullptr;
  const glm::vec3* normals = nullptr;    // unpacked as the GPU's snorm8 are when read
  const float* curvature = nullptr;      // or null: none computed
  const float* spacing = nullptr;        // or null
  const float* opacity = nullptr;        // opacity_draws: the splats' opacities, or null
  const uint32_t* order = nullptr;       // the queue order (chunk-local, from first), or null
  HostColors colors;
  float color_median = 0.0f;             // median_luminance of colors (0: the constant colour)
  uint32_t first = 0, count = 0;
  glm::mat4 view{1.0f};
  glm::mat3 normal_matrix{1.0f};
};

// What hatching_select.comp reads of a point, for its kernels.
struct SelectKernels {
  const HatchingSettings& u;
  const HostChunk& chunk_;  // (names the kernels do not use)
  const HostTexture& xtoon_;
  bool has_spacing() const { return chunk_.spacing != nullptr; }
  float point_spacing(uint index) const { return chunk_.spacing[index]; }
  bool has_opacity() const { return chunk_.opacity != nullptr; }
  float point_opacity(uint index) const { return chunk_.opacity[index]; }
  bool has_curvature() const { return chunk_.curvature != nullptr; }
  float point_curvature(uint index) const { return chunk_.curvature[index]; }
  vec3 point_color(uint index) const { return vec3(chunk_.colors.at(index)); }
  float point_color_median() const { return chunk_.color_median; }
  vec4 xtoon_image(vec2 uv) const { return xtoon_.sample(uv.x, uv.y); }
#include "hatching_kernels.glsl"
};

struct QuadKernels {
  const HatchingRasterSettings& raster;
#include "hatching_quad.glsl"
};

// point_attributes.glsl's view_normal() of a packed normal.
vec3 view_normal(const HostChunk& c, uint32_t index) {
  return unit_or_zero(c.normal_matrix * unpack_normal(pack_normal(c.normals[index])));
}

// Select: points [begin, end) of chunk c's draw order, kept in that order.
void select_strokes(SelectKernels kernels, uint32_t begin, uint32_t end, std::vector<Stroke>& out) {
  const HostChunk& c = kernels.chunk_;
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t index = c.first + (c.order ? c.order[i] : i);
    const Stroke s = kernels.place_stroke(index, c.ids[index], mat_vec(c.view, vec4(c.positions[index], 1.0f)),
                                          view_normal(c, index));
    if (!(s.center_alpha.w <= 0.0f)) out.push_back(s);
  }
}

// A line of a stroke as the rasterizer sees it.
struct Quad {
  StrokeQuad q;
  ExactQuad exact;
};

// Host images kept by the renderer from frame to frame.
struct Kept {
  HostInkImages ink;
  std::vector<float> surface;  // the depth pass's linear depth, +inf: none
  size_t bytes() const { return ink.bytes() + held_bytes(surface); }
};

}  // namespace

void draw_strokes_native(const MarkContext& ctx, const ParamValues& p, const StrokePass& pass) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const Rect clip = ctx.clip;
  uint32_t kept_strokes = 0, crossed = 0;
  auto report = [&] {
    if (!ctx.stats) return;
    (*ctx.stats)["strokes_drawn"] += double(kept_strokes);
    (*ctx.stats)["strokes_crossed"] += double(crossed);
  };
  if (clip.empty()) {
    if (ctx.coverage) *ctx.coverage = Rect{};
    report();
    return;
  }
  const glm::ivec2 size = clip.size();
  Kept& kept = ctx.host->get<Kept>();
  // The depth pass: the points mark's native discs, on the host.
  const bool test_depth = pass.depth_pass, clip_to_surface = pass.raster.clip_to_surface != 0;
  if (test_depth) {
    SplatSettings discs = pass.discs;
    discs.depth_only = &kept.surface;
    draw_splats_native(ctx, discs);
  }
  const float* surface = kept.surface.data();
  const HostInk ink = kept.ink.clear(clip);
  const HostTexture xtoon = pass.xtoon_image ? HostTexture(*pass.xtoon_image, "hatching") : HostTexture();
  // The depth the GL depth pass would hold (reversed Z, as points.vert).
  const float near = pass.raster.near_plane, far = pass.raster.far_plane;
  const bool ortho = pass.raster.ortho != 0;
  auto reversed_z = [near, far, ortho](float depth) {
    return ortho ? 1.0f - (depth - near) / (far - near) : near / depth;
  };

  // Host data of every chunk, held while drawing.
  std::vector<HostChunk> chunks(ctx.chunks.size());
  std::vector<std::shared_ptr<const void>> held;
  const PointCloud* opacity_cloud = nullptr;
  const GpuCloud* median_of = nullptr;  // median_luminance of its colours: once per cloud
  float median = 0.0f;
  const float* opacity_data = nullptr;
  for (size_t i = 0; i < ctx.chunks.size(); ++i) {
    const VisibleChunk& v = ctx.chunks[i];
    std::shared_ptr<const PointCloud> cloud = chunk_cloud(v, "hatching");
    geometry::Analysis& analysis = cloud->analysis();
    HostChunk& c = chunks[i];
    c.positions = cloud->local_positions().data();
    c.ids = cloud->point_index().data();
    if (v.gpu->own_normals) {
      c.normals = cloud->normals().data();
    } else {
      auto normals = analysis.normals({pass.normal_k, geometry::Orientation::Consistent, {}});
      c.normals = normals->data();
      held.push_back(normals);
    }
    if (pass.select.curvature_length > 0.0f) {
      auto curvature = analysis.curvature(pass.normal_k);
      c.curvature = curvature->data();
      held.push_back(curvature);
    }
    if (pass.select.coverage > 0.0f) {
      auto resolution = analysis.surface_resolution(pass.spacing_k);
      c.spacing = resolution->r.data();
      held.push_back(resolution);
    }
    if (pass.opacity_draws) {
      if (cloud.get() != opacity_cloud) {  // one array per cloud, not per chunk
        opacity_cloud = cloud.get();
        auto opacity = std::make_shared<const std::vector<float>>(splat_opacities(*cloud));
        opacity_data = opacity->data();
        held.push_back(opacity);
      }
      c.opacity = opacity_data;
    }
    if (draws_queue(v, p)) c.order = v.gpu->host_queue_order().data() + v.chunk->first;
    if (pass.select.coloring == 2) {
      c.colors = host_colors(*v.gpu, *cloud, pass.color_source, pass.select.constant_color);
      if (v.gpu != median_of) median_of = v.gpu, median = median_luminance(*v.gpu, *cloud, c.colors);  // per cloud
      c.color_median = median;
    }
    c.first = v.chunk->first;
    c.count = queue_count(v, p);
    c.view = v.view_from_chunk;
    c.normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_chunk)));
    held.push_back(cloud);
  }

  const QuadKernels quad_kernels{pass.raster};
  const glm::ivec2 origin = ctx.targets.origin;
  std::vector<Stroke> strokes;
  std::vector<Quad> quads;
  double select_ms = 0.0;
  size_t chunk = 0;
  while (chunk < chunks.size()) {
    // 1. Select, per batch of chunks: work items of points, in point order.
    const auto ts = Clock::now();
    std::vector<PointItem> items;
    size_t points = 0;
    for (; chunk < chunks.size() && (points == 0 || points + chunks[chunk].count <= kBatchStrokes); ++chunk) {
      points += chunks[chunk].count;
      add_point_items(items, uint32_t(chunk), chunks[chunk].count);
    }
    select_in_order(items, strokes, [&](const PointItem& item, std::vector<Stroke>& out) {
      select_strokes(SelectKernels{pass.select, chunks[item.chunk], xtoon}, item.begin, item.end, out);
    });
    for (const Stroke& s : strokes) {
      ++kept_strokes;
      crossed += s.n_width.w < 0.0f ? 1u : 0u;
      if (ctx.capture) ctx.capture->push_back(captured(s));
    }
    // 2. Two quads per stroke (the second only where it crosses), in the
    // GL's primitive order.
    quads.resize(2 * strokes.size());
    std::vector<uint8_t> alive(quads.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, quads.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      QuadKernels k = quad_kernels;
      for (size_t i = r.begin(); i < r.end(); ++i) {
        Quad& quad = quads[i];
        quad.q = k.stroke_quad(strokes[i / 2], uint(i % 2));
        alive[i] = 0;
        if (!(quad.q.size.x > 0.0f)) continue;
        const vec2 corners[4] = {k.quad_corner(quad.q, vec2(0.0f, 0.0f)), k.quad_corner(quad.q, vec2(1.0f, 0.0f)),
                                 k.quad_corner(quad.q, vec2(1.0f, 1.0f)), k.quad_corner(quad.q, vec2(0.0f, 1.0f))};
        alive[i] = exact_quad(corners, origin, clip, quad.exact) ? 1 : 0;
      }
    });
    size_t n = 0;
    for (size_t i = 0; i < quads.size(); ++i)
      if (alive[i]) quads[n++] = quads[i];
    quads.resize(n);
    select_ms += std::chrono::duration<double, std::milli>(Clock::now() - ts).count();

    // 3. Their pixels, blended per screen tile in quad order.
    auto bounds = [&](size_t i, glm::ivec2& lo, glm::ivec2& hi) {
      lo = quads[i].exact.lo;
      hi = quads[i].exact.hi;
      return true;
    };
    for_each_bin_in_order(quads.size(), clip, bounds, [&](const Rect& area, const uint32_t* list, size_t count) {
      QuadKernels k = quad_kernels;
      for (size_t j = 0; j < count; ++j) {
        const Quad& quad = quads[list[j]];
        for_each_covered_pixel(quad.exact, area, origin, [&](int x, int y) {
          const size_t q = ink.at(x, y);
          if (clip_to_surface && std::isinf(surface[q])) return;
          const vec4 hit = k.stroke_hit(quad.q, vec2(float(x + origin.x) + 0.5f, float(y + origin.y) + 0.5f));
          if (!(hit.x < 1e6f)) return;
          // GEQUAL against the discs' reversed Z (none: the far end, 0),
          // before the stroke's texture: hidden pixels cost no noise.
          if (test_depth && !std::isinf(surface[q]) && !(hit.z >= reversed_z(surface[q]))) return;
          const float a = k.stroke_coverage(quad.q, hit);
          if (a > 0.0f) ink.blend(q, vec3(quad.q.color), a, hit.w);
        });
      }
    });
  }
  const auto t1 = Clock::now();

  // 4. Ink over paper (ink_resolve.comp), uploaded.
  auto surface_at = [surface, test_depth](size_t q) {
    return test_depth ? surface[q] : std::numeric_limits<float>::infinity();
  };
  const std::vector<glm::ivec2> row_span = resolve_ink(ink, size, pass.paper, surface_at);
  upload_cpu_mark(ctx.targets, clip, ink.accum, ink.depth, row_span, ctx.coverage, "hatching");
  report();
  if (ctx.stats) {
    auto ms = [](Clock::time_point a, Clock::time_point b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    (*ctx.stats)["native_select_ms"] += select_ms;
    (*ctx.stats)["native_strokes_ms"] += ms(t0, t1) - select_ms;
  }
}

}  // namespace pointnpr::hatching
