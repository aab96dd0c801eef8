// The points mark's native rasterizer: the compute rasterizer's rules
// (shaders/points.comp, points.glsl, point_attributes.glsl) on the CPU's
// threads (TBB), for software GL devices, where llvmpipe's per-pixel
// atomics of the compute passes cost several times a plain scatter.
//
// Two passes. Scatter: every point (of the chunk's resolution queue when it
// is on) projected as the compute path does and its splat's pixels given
// min(depth bits << 32 | point key) by an atomic fetch-min, so the winner
// is the nearest point, ties to the smallest key, whatever order the
// threads ran in. Resolve: each covered pixel's colour from its winning
// point alone (one colour per pixel, not per splat pixel), then colour and
// depth uploaded over the clip rectangle into the mark's images.
#include <algorithm>
#include <bit>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/hash.h"
#include "geometry/analysis.h"
#include "gl/device.h"
#include "marks/points/points.h"
#include "render/native_raster.h"
#include "render/point_color.h"
#include "scene/camera.h"
#include "scene/splat_attributes.h"

namespace pointnpr {

glm::vec4 HostColors::at(uint32_t index) const {
  switch (source) {
    case ColorSource::Rgb: return glsl::attribute_color(0, colors[index], 1.0f, constant);
    case ColorSource::Intensity: return glsl::attribute_color(1, std::bit_cast<uint32_t>(intensity[index]), intensity_scale, constant);
    case ColorSource::Classification: return glsl::attribute_color(2, classification[index], 1.0f, constant);
    default: return glsl::attribute_color(3, 0u, 1.0f, constant);
  }
}

HostColors host_colors(const GpuCloud& gpu, const PointCloud& cloud, ColorSource source, glm::vec4 constant) {
  HostColors c;
  c.source = resolve_color_source(source, gpu);
  c.colors = cloud.colors().data();
  c.intensity = cloud.intensity().data();
  c.classification = cloud.classification().data();
  c.intensity_scale = gpu.intensity_scale;
  c.constant = constant;
  return c;
}

float median_luminance(const GpuCloud& gpu, const PointCloud& cloud, const HostColors& colors) {
  if (colors.source == ColorSource::Constant || cloud.size() == 0) return 0.0f;
  float& median = gpu.host_slot<float>("median_luminance:" + std::to_string(int(colors.source)));
  if (median > 0.0f) return median;
  const size_t n = cloud.size(), step = std::max<size_t>(1, n / 65536);
  std::vector<float> lum;
  lum.reserve(n / step + 1);
  for (size_t i = 0; i < n; i += step)
    lum.push_back(glm::dot(glm::vec3(colors.at(uint32_t(i))), glm::vec3(0.2126f, 0.7152f, 0.0722f)));
  std::nth_element(lum.begin(), lum.begin() + long(lum.size() / 2), lum.end());
  median = std::max(lum[lum.size() / 2], 1.0f / 255.0f);  // a black scan: every colour its own tone
  return median;
}

namespace {

constexpr uint64_t kEmpty = ~uint64_t(0);

// One chunk as the scatter sees it: its float rows of the view depth and of
// the projection (x, y, w), composed in double from the chunk's transform.
struct ScatterChunk {
  const glm::vec3* positions = nullptr;  // the chunk's first point
  const uint32_t* order = nullptr;       // queue order (chunk-local indices), or null: all in index order
  uint32_t count = 0;
  uint32_t key_base = 0;
  glm::vec4 depth_row{0.0f};  // -view z
  glm::vec4 clip_x{0.0f}, clip_y{0.0f}, clip_w{0.0f};
  // Per point (chunk-local) its SplatRadius (size_mode splat or spacing:
  // points.glsl) and, for Gaussian-splat captures with ids, the opacity a hash of
  // its id is drawn under; null: the frame's size, every point drawn.
  const float* splat_radius = nullptr;
  const float* opacity = nullptr;
  const uint32_t* ids = nullptr;
};

// What the resolve needs of a chunk to colour its points (point_color()).
struct ColorChunk {
  uint32_t key_base = 0;
  uint32_t count = 0;
  uint32_t first = 0;  // the chunk's first point in the cloud's arrays
  HostColors colors;
  const glm::vec3* normals = nullptr;  // cloud order, or null: unlit
  glm::mat3 normal_matrix{1.0f};
  const float* radius = nullptr;  // cloud order: the points' spacing (SplatRadius), where it is written
  float spacing_scale = 1.0f;     // its view scale (points.glsl u_spacing_scale)
};

// The frame-wide numbers of points.glsl's uniforms.
struct Frame {
  glm::vec2 size{0.0f};    // the whole frame's (the projection maps to it)
  glm::vec2 origin{0.0f};  // the tile's
  Rect clip;               // tile pixels
  float near = 0.0f, far = 0.0f;
  bool ortho = false;
  bool world_size = false;
  float point_size = 2.0f, world_size_units = 0.05f, px_per_unit = 1.0f;
  float radius_diameters = 2.0f, min_pixels = 0.0f;  // SplatSettings'
};

glm::vec4 row(const glm::dmat4& m, int r) { return {float(m[0][r]), float(m[1][r]), float(m[2][r]), float(m[3][r])}; }

float dot_affine(const glm::vec4& row, const glm::vec3& p) { return row.x * p.x + row.y * p.y + row.z * p.z + row.w; }

// points.glsl's kOpacitySalt.
constexpr uint32_t kOpacitySalt = 0x6f706163u;

// covers() of points.glsl, evaluated in the same float operations.
bool covers(float dx, float dy, float diameter) {
  const float r = 0.5f * diameter;
  if (diameter < 2.0f) return std::abs(dx) <= r && std::abs(dy) <= r;
  return dx * dx + dy * dy <= r * r;
}

// Specialised on what is constant over a frame: the size mode, the
// camera's kind, whether the queue orders the points.
template <bool kWorldSize, bool kOrtho, bool kQueue>
void scatter_chunk(const ScatterChunk& c, const Frame& f, uint64_t* keys, int stride, uint32_t begin, uint32_t end) {
  const float lo_x = float(f.clip.min.x) - 1.0f, lo_y = float(f.clip.min.y) - 1.0f;
  const float hi_x = float(f.clip.max.x) + 1.0f, hi_y = float(f.clip.max.y) + 1.0f;
  uint64_t* rows = keys - size_t(f.clip.min.y) * size_t(stride) - f.clip.min.x;  // by frame pixel
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t local = kQueue ? c.order[i] : i;
    const glm::vec3 p = c.positions[local];
    const float depth = dot_affine(c.depth_row, p);
    if (!(depth >= f.near && depth <= f.far)) continue;
    if (c.opacity && !(glsl::id_rand(c.ids[local], kOpacitySalt, 0u) < c.opacity[local])) continue;
    const float w = dot_affine(c.clip_w, p);
    const float cx = (dot_affine(c.clip_x, p) / w * 0.5f + 0.5f) * f.size.x - f.origin.x;
    const float cy = (dot_affine(c.clip_y, p) / w * 0.5f + 0.5f) * f.size.y - f.origin.y;
    const float units = kWorldSize && c.splat_radius ? f.radius_diameters * c.splat_radius[local] : f.world_size_units;
    const float diameter =
        kWorldSize
            ? std::max(std::clamp(units * f.px_per_unit / (kOrtho ? 1.0f : depth), 1.0f, kMaxSplatPixels), f.min_pixels)
            : f.point_size;
    const float r = 0.5f * diameter;
    // Off the clip rectangle (or not finite): nothing to cover, and no
    // float too large for an int below.
    if (!(cx + r >= lo_x && cx - r <= hi_x && cy + r >= lo_y && cy - r <= hi_y)) continue;
    const int x0 = std::max(floor_int(cx - r), f.clip.min.x), x1 = std::min(ceil_int(cx + r), f.clip.max.x - 1);
    const int y0 = std::max(floor_int(cy - r), f.clip.min.y), y1 = std::min(ceil_int(cy + r), f.clip.max.y - 1);
    uint32_t depth_bits;
    std::memcpy(&depth_bits, &depth, 4);  // positive floats order as their bits
    const uint64_t packed = uint64_t(depth_bits) << 32 | uint64_t(c.key_base + local);
    if (diameter < 2.0f) {
      // The square rule is separable, and below 2 px a side covers at most
      // two of the pixel centres nearest the splat's, m - 1, m, m + 1 (m:
      // the pixel holding it): test the three, without branches to
      // mispredict on the common case of just m.
      auto covered_span = [r](float centre, int& first) {
        const int m = floor_int(centre);
        auto in = [&](int v) { return std::abs(float(v) + 0.5f - centre) <= r; };
        const bool below = in(m - 1), at = in(m), above = in(m + 1);
        first = below ? m - 1 : (at ? m : m + 1);
        const int last = above ? m + 1 : (at ? m : m - 1);
        return last - first + 1;  // <= 0: no centre covered
      };
      int fx, fy;
      const int nx = covered_span(cx, fx), ny = covered_span(cy, fy);
      const int xa = std::max(fx, x0), xb = std::min(fx + nx - 1, x1);
      const int ya = std::max(fy, y0), yb = std::min(fy + ny - 1, y1);
      for (int y = ya; y <= yb; ++y) {
        uint64_t* line = rows + size_t(y) * size_t(stride);
        for (int x = xa; x <= xb; ++x) fetch_min(line[x], packed);
      }
      continue;
    }
    for (int y = y0; y <= y1; ++y) {
      const float dy = float(y) + 0.5f - cy;
      uint64_t* line = rows + size_t(y) * size_t(stride);
      for (int x = x0; x <= x1; ++x)
        if (covers(float(x) + 0.5f - cx, dy, diameter)) fetch_min(line[x], packed);
    }
  }
}

using ScatterFn = void (*)(const ScatterChunk&, const Frame&, uint64_t*, int, uint32_t, uint32_t);

ScatterFn scatter_function(bool world_size, bool ortho, bool queue) {
  static constexpr ScatterFn kTable[8] = {
      scatter_chunk<false, false, false>, scatter_chunk<false, false, true>, scatter_chunk<false, true, false>,
      scatter_chunk<false, true, true>,   scatter_chunk<true, false, false>,  scatter_chunk<true, false, true>,
      scatter_chunk<true, true, false>,   scatter_chunk<true, true, true>};
  return kTable[(world_size ? 4 : 0) + (ortho ? 2 : 0) + (queue ? 1 : 0)];
}

// The host images of the last frames, kept by the renderer (HostScratch) so
// that a frame does not page-fault tens of megabytes in anew (bounded by the
// largest image, a tile's region at most).
struct HostImages {
  std::vector<uint64_t> keys;
  std::vector<float> rgba, depth, spacing;
  size_t bytes() const { return held_bytes(keys) + held_bytes(rgba) + held_bytes(depth) + held_bytes(spacing); }
};
HostImages& host_images(HostScratch& host, size_t pixels, bool spacing) {
  HostImages& images = host.get<HostImages>();
  if (images.keys.size() < pixels) {
    images.keys.resize(pixels);
    images.rgba.resize(4 * pixels);
    images.depth.resize(pixels);
  }
  if (spacing && images.spacing.size() < pixels) images.spacing.resize(pixels);
  return images;
}

glm::vec4 point_color(const ColorChunk& c, uint32_t local, const SplatSettings& s) {
  const uint32_t index = c.first + local;
  const glm::vec4 color = c.colors.at(index);
  if (!s.shading) return color;
  // What the GPU paths read: the snorm8 normal, turned into view space.
  const glm::vec3 n = c.normals ? glsl::unit_or_zero(c.normal_matrix * unpack_normal(pack_normal(c.normals[index])))
                                : glm::vec3(0.0f);
  return glm::vec4(glsl::diffuse_shaded(glm::vec3(color), n, s.light_dir, s.shading_strength), color.a);
}

}  // namespace

void draw_splats_native(const MarkContext& ctx, const SplatSettings& s) {
  const Rect clip = ctx.clip;
  if (clip.empty()) {
    if (ctx.coverage) *ctx.coverage = Rect{};
    return;
  }
  const Camera& cam = *ctx.camera;
  const glm::ivec2 frame_px = frame_size(ctx.targets);
  Frame f;
  f.size = glm::vec2(frame_px);
  f.origin = glm::vec2(ctx.targets.origin);
  f.clip = clip;
  f.near = float(cam.clip_start);
  f.far = float(cam.clip_end);
  f.ortho = cam.orthographic;
  f.world_size = s.world_size;
  f.point_size = s.point_size;
  f.world_size_units = s.world_diameter;
  f.radius_diameters = s.radius_diameters;
  f.min_pixels = s.min_pixels;
  f.px_per_unit = float(cam.pixels_per_unit(1.0, frame_px.y));

  // Host data of every chunk; the analyses' normals are held while drawing.
  std::vector<ScatterChunk> scatter(ctx.chunks.size());
  std::vector<ColorChunk> color(ctx.chunks.size());
  std::vector<std::shared_ptr<const PointCloud>> clouds;
  std::vector<std::shared_ptr<const std::vector<glm::vec3>>> estimated;
  std::vector<std::shared_ptr<const std::vector<float>>> splat_data;  // radii, opacities (cloud order)
  const float* last_radius = nullptr;
  const float* last_opacity = nullptr;
  const PointCloud* last_cloud = nullptr;
  const glm::vec3* last_normals = nullptr;
  for (size_t i = 0; i < ctx.chunks.size(); ++i) {
    const VisibleChunk& v = ctx.chunks[i];
    std::shared_ptr<const PointCloud> cloud = chunk_cloud(v, "points");
    if (cloud.get() != last_cloud) {
      last_cloud = cloud.get();
      last_normals = nullptr;
      if (s.shading) {
        if (v.gpu->own_normals) {
          last_normals = cloud->normals().data();
        } else {
          estimated.push_back(cloud->analysis().normals({s.normal_k, geometry::Orientation::Consistent, {}}));
          last_normals = estimated.back()->data();
        }
      }
      last_radius = last_opacity = nullptr;
      if (s.splat_size || ctx.targets.spacing) {
        splat_data.push_back(shared_splat_radii(*cloud, s.splat_k));
        last_radius = splat_data.back()->data();
      }
      if (s.opacity_draws) {
        splat_data.push_back(std::make_shared<const std::vector<float>>(splat_opacities(*cloud)));
        last_opacity = splat_data.back()->data();
      }
      clouds.push_back(cloud);
    }
    const glm::dmat4 view(v.view_from_chunk);
    const glm::dmat4 clip_from_chunk = cam.projection * view;
    ScatterChunk& sc = scatter[i];
    sc.positions = cloud->local_positions().data() + v.chunk->first;
    sc.count = v.chunk->count;
    if (!s.queue_counts.empty()) {
      sc.order = v.gpu->host_queue_order().data() + v.chunk->first;
      sc.count = s.queue_counts[i];
    }
    sc.key_base = v.key_base;
    if (last_radius && s.splat_size) sc.splat_radius = last_radius + v.chunk->first;
    if (last_opacity) {
      sc.opacity = last_opacity + v.chunk->first;
      sc.ids = cloud->point_index().data() + v.chunk->first;
    }
    // Depth from the float view transform, as the GPU paths (-v.z).
    const glm::vec4 z_row(v.view_from_chunk[0][2], v.view_from_chunk[1][2], v.view_from_chunk[2][2],
                          v.view_from_chunk[3][2]);
    sc.depth_row = -z_row;
    sc.clip_x = row(clip_from_chunk, 0);
    sc.clip_y = row(clip_from_chunk, 1);
    sc.clip_w = row(clip_from_chunk, 3);
    ColorChunk& cc = color[i];
    cc.key_base = v.key_base;
    cc.count = v.chunk->count;
    cc.first = v.chunk->first;
    cc.colors = host_colors(*v.gpu, *last_cloud, s.color_source, s.constant_color);
    cc.normals = last_normals;
    cc.normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_chunk)));
    if (ctx.targets.spacing) {
      cc.radius = last_radius;
      cc.spacing_scale = view_scale(v);
    }
  }

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  // Scatter. Work items of at most kPointGrain points, so one big chunk (or
  // many small ones) still spreads over the threads.
  const glm::ivec2 size = clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  const bool write_spacing = ctx.targets.spacing && !s.depth_only;
  HostImages& host = host_images(*ctx.host, pixels, write_spacing);
  float* spacing = write_spacing ? host.spacing.data() : nullptr;
  uint64_t* keys = host.keys.data();
  float* rgba = host.rgba.data();
  float* depth = host.depth.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(keys + r.begin(), keys + r.end(), kEmpty);
  });
  std::vector<PointItem> items;
  for (size_t i = 0; i < scatter.size(); ++i) add_point_items(items, uint32_t(i), scatter[i].count);
  const ScatterFn scatter_points = scatter_function(f.world_size, f.ortho, !s.queue_counts.empty());
  for_each_point_item(items, [&](const PointItem& item) {
    scatter_points(scatter[item.chunk], f, keys, size.x, item.begin, item.end);
  });

  const auto t1 = Clock::now();
  if (s.depth_only) {
    s.depth_only->resize(pixels);
    float* out = s.depth_only->data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t p = r.begin(); p < r.end(); ++p)
        out[p] = keys[p] == kEmpty ? std::numeric_limits<float>::infinity()
                                   : std::bit_cast<float>(uint32_t(keys[p] >> 32));
    });
    if (ctx.stats) (*ctx.stats)["native_discs_ms"] += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    return;
  }
  // Resolve: a pixel's winner by its key (the chunks are in key order).
  // Each row's covered columns [first, last]: the covered bounds, for free.
  std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    size_t hint = 0;
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < size.x; ++x) {
        const size_t p = size_t(y) * size_t(size.x) + size_t(x);
        const uint64_t packed = keys[p];
        if (packed == kEmpty) {
          std::fill(&rgba[4 * p], &rgba[4 * p + 4], 0.0f);
          depth[p] = std::numeric_limits<float>::infinity();
          if (spacing) spacing[p] = 0.0f;
          continue;
        }
        const uint32_t key = uint32_t(packed);
        const uint32_t depth_bits = uint32_t(packed >> 32);
        if (key - color[hint].key_base >= color[hint].count) {
          auto it = std::upper_bound(color.begin(), color.end(), key,
                                     [](uint32_t k, const ColorChunk& c) { return k < c.key_base; });
          hint = size_t(it - color.begin()) - 1;
        }
        row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, x), x};
        const glm::vec4 c = point_color(color[hint], key - color[hint].key_base, s);
        std::memcpy(&rgba[4 * p], &c, 16);
        std::memcpy(&depth[p], &depth_bits, 4);
        // As points.glsl's point_spacing (the same float product).
        if (spacing) {
          const ColorChunk& cc = color[hint];
          spacing[p] = cc.radius[cc.first + key - cc.key_base] * cc.spacing_scale;
        }
      }
  });

  const auto t2 = Clock::now();
  upload_cpu_mark(ctx.targets, clip, rgba, depth, row_span, ctx.coverage, "points");
  if (spacing) {
    glTextureSubImage2D(ctx.targets.spacing->id(), 0, clip.min.x, clip.min.y, size.x, size.y, GL_RED, GL_FLOAT, spacing);
    gl::check_gl("points: native spacing upload");
  }
  if (ctx.stats) {
    auto ms = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    (*ctx.stats)["native_scatter_ms"] += ms(t0, t1);
    (*ctx.stats)["native_resolve_ms"] += ms(t1, t2);
    (*ctx.stats)["native_upload_ms"] += ms(t2, Clock::now());
  }
}

}  // namespace pointnpr
