// The gaussians mark on the CPU's threads (TBB): the 3DGS reference
// rasterizer's forward pass (Kerbl et al. 2023) over screen tiles.
//
// 1. Preprocess, in parallel over the splats: floaters dropped (opacity,
//    scale, isolation), the 3D covariance projected to a 2D conic
//    (shaders/gaussians_kernels.glsl, shared with the GLSL), the colour
//    from the SH bands seen from the camera, the tiles its 3-sigma square
//    reaches. Each splat writes its own record: no order depends on threads.
// 2. Bin, in splat order: each 16 px tile's list of the splats reaching it.
// 3. Per tile, in parallel: the list sorted by (view depth, point key), a
//    total order, then each pixel composited front to back in display sRGB
//    (alpha <= 0.99, skipped below 1/255, stopped once the transmittance
//    would fall below 1e-4). Its depth is the view depth of the splat at
//    which its opacity first reaches depth_alpha (else of the splat that
//    gave it most), its coverage the opacity.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/glsl.h"
#include "geometry/analysis.h"
#include "geometry/features.h"
#include "marks/gaussians/gaussians.h"
#include "render/native_raster.h"
#include "scene/camera.h"
#include "scene/gaussian_splats.h"
#include "scene/point_cloud.h"

namespace pointnpr::gaussians {
namespace {

using namespace glsl;
#include "gaussians_settings.glsl"

struct Kernels {
  const GaussianSettings& u;
  const float* sh = nullptr;
  int coefficients = 1;
  vec3 sh_at(uint base, int k) const {
    const float* p = sh + (size_t(base) * size_t(coefficients) + size_t(k)) * 3;
    return vec3(p[0], p[1], p[2]);
  }
#include "gaussians_kernels.glsl"
};

constexpr int kTile = 16;

struct Record {
  vec2 center{0.0f};
  vec3 conic{0.0f};
  vec3 color{0.0f};
  float opacity = 0.0f;
  float skip_below = 0.0f;  // a power below this gives an alpha under 1/255 (with a margin): no exp needed
  float depth = 0.0f;
  uint32_t key = 0;
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;      // pixels it may reach (inclusive, the images' coordinates)
  int tx0 = 0, ty0 = 0, tx1 = -1, ty1 = -1;  // tiles reached (inclusive); tx1 < tx0: not drawn
};

struct Chunk {
  const PointCloud* cloud = nullptr;
  const GaussianSplats* g = nullptr;
  const float* isolation_r = nullptr;
  float isolation_limit = 0.0f;
  uint32_t first = 0, count = 0, key_base = 0;
  const uint32_t* order = nullptr;  // the queue order (chunk-local indices), or null: all in index order
  size_t record_base = 0;
  mat4 view{1.0f};
  mat3 view_rows{1.0f};
  vec3 camera{0.0f};       // chunk-local camera position (perspective)
  vec3 view_dir{0.0f};     // chunk-local viewing direction (orthographic)
};

// The kernels' per-pixel functions, outside a Kernels (they read no settings).
const GaussianSettings kNoSettings{};
float splat_power_host(vec3 conic, float dx, float dy) { return Kernels{kNoSettings}.splat_power(conic, dx, dy); }
float alpha_of_power_host(float power, float opacity) { return Kernels{kNoSettings}.alpha_of_power(power, opacity); }

struct HostImages {
  std::vector<float> rgba, depth;
  size_t bytes() const { return held_bytes(rgba) + held_bytes(depth); }
};

}  // namespace

DrawCounts draw_native(const MarkContext& ctx, const DrawSettings& s) {
  DrawCounts counts;
  const Rect clip = ctx.clip;
  if (clip.empty()) {
    if (ctx.coverage) *ctx.coverage = Rect{};
    return counts;
  }
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const Camera& cam = *ctx.camera;
  const glm::ivec2 frame_px = frame_size(ctx.targets);
  GaussianSettings u{};
  const glm::dmat4& P = cam.projection;
  auto prow = [&](int r) { return vec4(float(P[0][r]), float(P[1][r]), float(P[2][r]), float(P[3][r])); };
  u.proj_row0 = prow(0);
  u.proj_row1 = prow(1);
  u.proj_row3 = prow(3);
  u.frame = vec4(float(frame_px.x), float(frame_px.y), float(ctx.targets.origin.x), float(ctx.targets.origin.y));
  u.near_far = vec4(float(cam.clip_start), float(cam.clip_end), 0.0f, 0.0f);
  u.ortho = cam.orthographic ? 1 : 0;
  u.dilation = 0.3f;
  u.max_radius = s.max_radius;
  u.sh_degree = s.sh_degree;

  // The chunks' host data (clouds held while drawing).
  std::vector<Chunk> chunks;
  std::vector<std::shared_ptr<const PointCloud>> clouds;
  std::vector<std::shared_ptr<const geometry::LocalResolution>> isolation;
  size_t total = 0;
  for (size_t i = 0; i < ctx.chunks.size(); ++i) {
    const VisibleChunk& v = ctx.chunks[i];
    std::shared_ptr<const PointCloud> cloud = chunk_cloud(v, "gaussians");
    if (!cloud->gaussians()) {
      counts.plain_points += v.chunk->count;
      continue;
    }
    Chunk c;
    c.cloud = cloud.get();
    c.g = cloud->gaussians();
    if (s.isolation > 0.0f) {
      if (isolation.empty() || clouds.back().get() != cloud.get())
        isolation.push_back(cloud->analysis().local_resolution(8));
      c.isolation_r = isolation.back()->r.data();
      c.isolation_limit = s.isolation * isolation.back()->median_r;
    }
    if (clouds.empty() || clouds.back().get() != cloud.get()) clouds.push_back(cloud);
    c.first = v.chunk->first;
    c.count = v.chunk->count;
    if (!s.queue_counts.empty()) {
      c.order = v.gpu->host_queue_order().data() + v.chunk->first;
      c.count = s.queue_counts[i];
    }
    c.key_base = v.key_base;
    c.record_base = total;
    total += c.count;
    c.view = v.view_from_chunk;
    c.view_rows = mat3(c.view[0][0], c.view[1][0], c.view[2][0], c.view[0][1], c.view[1][1], c.view[2][1],
                       c.view[0][2], c.view[1][2], c.view[2][2]);
    const glm::dmat4 chunk_from_view = glm::inverse(glm::dmat4(v.view_from_chunk));
    c.camera = vec3(chunk_from_view * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    c.view_dir = vec3(glm::normalize(glm::dvec3(chunk_from_view * glm::dvec4(0.0, 0.0, -1.0, 0.0))));
    chunks.push_back(c);
  }

  const glm::ivec2 size = clip.size();
  const int tiles_x = (size.x + kTile - 1) / kTile, tiles_y = (size.y + kTile - 1) / kTile;
  std::vector<Record> records(total);
  std::vector<uint8_t> dropped(total, 0);  // 1: floater, 2: culled
  // 1. Preprocess.
  std::vector<PointItem> items;
  for (size_t i = 0; i < chunks.size(); ++i) add_point_items(items, uint32_t(i), chunks[i].count);
  for_each_point_item(items, [&](const PointItem& item) {
    const Chunk& c = chunks[item.chunk];
    Kernels k{u, c.g->sh.data(), c.g->coefficients()};
    const int degree = std::min(s.sh_degree, c.g->sh_degree);
    const glm::vec3* positions = c.cloud->local_positions().data();
    for (uint32_t i = item.begin; i < item.end; ++i) {
      const uint32_t local = c.order ? c.order[i] : i;
      const uint32_t index = c.first + local;
      const size_t r = c.record_base + i;
      const float opacity = c.g->opacity[index];
      const vec3 scale = c.g->scales[index];
      if ((s.min_opacity > 0.0f && opacity < s.min_opacity) ||
          (s.max_scale > 0.0f && std::max({scale.x, scale.y, scale.z}) > s.max_scale) ||
          (c.isolation_r && c.isolation_limit > 0.0f && c.isolation_r[index] > c.isolation_limit)) {
        dropped[r] = 1;
        continue;
      }
      const vec3 p = positions[index];
      const vec3 t = vec3(mat_vec(c.view, vec4(p, 1.0f)));
      const Kernels::ScreenSplat ss = k.project_splat(t, k.view_covariance(c.view_rows, c.g->rotations[index], scale));
      dropped[r] = 2;
      if (!(ss.radius > 0.0f)) continue;
      // Anti-aliased captures: the 2D filter's compensation (Mip-Splatting).
      const float drawn_opacity = c.g->antialiased ? opacity * std::sqrt(ss.det_ratio) : opacity;
      // The pixels it can reach: those of its 3-sigma square (the reference's
      // [floor(c - r), ceil(c + r)]) whose centre lies in the ellipse where
      // its alpha reaches 1/255 (1/2 d^T S^-1 d <= ln(255 o)): outside it the
      // alpha is skipped anyway, so the box changes no pixel, and no pixel's
      // result depends on how the frame is cut into tiles.
      const float reach = std::log(255.0f * drawn_opacity);
      if (!(reach > 0.0f)) continue;
      const float det = ss.conic.x * ss.conic.z - ss.conic.y * ss.conic.y;
      const float ex = std::sqrt(2.0f * reach * ss.conic.z / det) * 1.001f + 0.01f;
      const float ey = std::sqrt(2.0f * reach * ss.conic.x / det) * 1.001f + 0.01f;
      if (!(ex > 0.0f && ey > 0.0f && std::isfinite(ex) && std::isfinite(ey))) continue;
      const vec2 lo = ss.center - vec2(ss.radius), hi = ss.center + vec2(ss.radius);
      if (!(hi.x >= float(clip.min.x) && lo.x <= float(clip.max.x) && hi.y >= float(clip.min.y) &&
            lo.y <= float(clip.max.y)))
        continue;
      const int x0 = std::max({floor_int(lo.x), ceil_int(ss.center.x - ex - 0.5f), clip.min.x});
      const int x1 = std::min({ceil_int(hi.x), floor_int(ss.center.x + ex - 0.5f), clip.max.x - 1});
      const int y0 = std::max({floor_int(lo.y), ceil_int(ss.center.y - ey - 0.5f), clip.min.y});
      const int y1 = std::min({ceil_int(hi.y), floor_int(ss.center.y + ey - 0.5f), clip.max.y - 1});
      if (x1 < x0 || y1 < y0) continue;
      dropped[r] = 0;
      Record& rec = records[r];
      rec.center = ss.center;
      rec.conic = ss.conic;
      rec.depth = ss.depth;
      rec.opacity = drawn_opacity;
      rec.skip_below = -reach - 1e-3f;
      rec.key = c.key_base + local;
      const vec3 dir = u.ortho != 0 ? c.view_dir : glm::normalize(p - c.camera);
      rec.color = k.sh_color(index, degree, dir);
      rec.x0 = x0 - clip.min.x, rec.x1 = x1 - clip.min.x, rec.y0 = y0 - clip.min.y, rec.y1 = y1 - clip.min.y;
      rec.tx0 = (x0 - clip.min.x) / kTile, rec.tx1 = (x1 - clip.min.x) / kTile;
      rec.ty0 = (y0 - clip.min.y) / kTile, rec.ty1 = (y1 - clip.min.y) / kTile;
    }
  });
  const auto t1 = Clock::now();

  // 2. Bin, in record order (counting sort: deterministic lists).
  const size_t tiles = size_t(tiles_x) * size_t(tiles_y);
  std::vector<uint32_t> start(tiles + 1, 0);
  for (size_t r = 0; r < total; ++r) {
    if (dropped[r] == 1) ++counts.floaters;
    if (dropped[r] == 2) ++counts.culled;
    if (dropped[r] != 0) continue;
    const Record& rec = records[r];
    for (int ty = rec.ty0; ty <= rec.ty1; ++ty)
      for (int tx = rec.tx0; tx <= rec.tx1; ++tx) ++start[size_t(ty) * size_t(tiles_x) + size_t(tx) + 1];
    ++counts.drawn;
  }
  for (size_t t = 1; t <= tiles; ++t) start[t] += start[t - 1];
  std::vector<uint32_t> lists(start[tiles]);
  {
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    for (size_t r = 0; r < total; ++r) {
      if (dropped[r] != 0) continue;
      const Record& rec = records[r];
      for (int ty = rec.ty0; ty <= rec.ty1; ++ty)
        for (int tx = rec.tx0; tx <= rec.tx1; ++tx) lists[next[size_t(ty) * size_t(tiles_x) + size_t(tx)]++] = uint32_t(r);
    }
  }
  const auto t2 = Clock::now();

  // 3. Each tile's list sorted by (view depth, point key): a total order.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles, 1), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t t = range.begin(); t < range.end(); ++t)
      std::sort(lists.data() + start[t], lists.data() + start[t + 1], [&](uint32_t a, uint32_t b) {
        const Record& ra = records[a];
        const Record& rb = records[b];
        return ra.depth < rb.depth || (ra.depth == rb.depth && ra.key < rb.key);
      });
  });
  auto report = [&](Clock::time_point t3) {
    if (!ctx.stats) return;
    auto ms = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    (*ctx.stats)["gaussians_preprocess_ms"] += ms(t0, t1);
    (*ctx.stats)["gaussians_bin_ms"] += ms(t1, t2);
    (*ctx.stats)["gaussians_raster_ms"] += ms(t2, t3);
    (*ctx.stats)["gaussians_drawn"] += double(counts.drawn);
    (*ctx.stats)["gaussians_floaters"] += double(counts.floaters);
    (*ctx.stats)["gaussians_culled"] += double(counts.culled);
    (*ctx.stats)["gaussians_tile_entries"] += double(lists.size());
  };
  if (s.gl) {
    std::vector<GpuRecord> gpu(records.size());
    tbb::parallel_for(size_t(0), records.size(), [&](size_t r) {
      const Record& rec = records[r];
      gpu[r] = {vec4(rec.center, rec.depth, rec.opacity), vec4(rec.conic, 0.0f), vec4(rec.color, 1.0f),
                glm::ivec4(rec.x0, rec.y0, rec.x1, rec.y1)};
    });
    composite_gl(ctx, s, gpu, start, lists, tiles_x, tiles_y);
    report(Clock::now());
    return counts;
  }

  // 4. Composite, tile by tile.
  HostImages& host = ctx.host->get<HostImages>();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  if (host.depth.size() < pixels) {
    host.rgba.resize(4 * pixels);
    host.depth.resize(pixels);
  }
  float* rgba = host.rgba.data();
  float* depth = host.depth.data();
  std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
  std::vector<glm::ivec2> tile_span(tiles * kTile, glm::ivec2(size.x, -1));  // per tile, per row in it
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles, 1), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t t = range.begin(); t < range.end(); ++t) {
      const uint32_t* list = lists.data() + start[t];
      const size_t n = start[t + 1] - start[t];
      const int tx = int(t % size_t(tiles_x)), ty = int(t / size_t(tiles_x));
      const int xa = tx * kTile, xb = std::min(xa + kTile, size.x);
      const int ya = ty * kTile, yb = std::min(ya + kTile, size.y);
      // Splat after splat (each pixel sees them in the sorted order), over
      // the pixels of its box in this tile; a tile whose every pixel has
      // terminated stops early.
      constexpr float kNone = std::numeric_limits<float>::infinity();
      float T[kTile * kTile], d[kTile * kTile], best_weight[kTile * kTile], best_depth[kTile * kTile];
      vec3 C[kTile * kTile];
      bool done[kTile * kTile];
      std::fill(T, T + kTile * kTile, 1.0f);
      std::fill(d, d + kTile * kTile, kNone);
      std::fill(best_weight, best_weight + kTile * kTile, 0.0f);
      std::fill(best_depth, best_depth + kTile * kTile, kNone);
      std::fill(C, C + kTile * kTile, vec3(0.0f));
      std::fill(done, done + kTile * kTile, false);
      int alive = (xb - xa) * (yb - ya);
      for (size_t i = 0; i < n && alive > 0; ++i) {
        const Record& rec = records[list[i]];
        const int x0 = std::max(rec.x0, xa), x1 = std::min(rec.x1, xb - 1);
        const int y0 = std::max(rec.y0, ya), y1 = std::min(rec.y1, yb - 1);
        for (int y = y0; y <= y1; ++y) {
          const float py = float(clip.min.y + y) + 0.5f;
          for (int x = x0; x <= x1; ++x) {
            const int q = (y - ya) * kTile + (x - xa);
            if (done[q]) continue;
            const float px = float(clip.min.x + x) + 0.5f;
            const float power = splat_power_host(rec.conic, rec.center.x - px, rec.center.y - py);
            if (power < rec.skip_below) continue;  // alpha_of_power() would give 0 (below 1/255)
            const float alpha = alpha_of_power_host(power, rec.opacity);
            if (alpha == 0.0f) continue;
            const float test = T[q] * (1.0f - alpha);
            if (test < 1e-4f) {
              done[q] = true;
              --alive;
              continue;
            }
            const float weight = alpha * T[q];
            C[q] += rec.color * weight;
            if (weight > best_weight[q]) best_weight[q] = weight, best_depth[q] = rec.depth;
            if (d[q] == kNone && 1.0f - test >= s.depth_alpha) d[q] = rec.depth;
            T[q] = test;
          }
        }
      }
      for (int y = ya; y < yb; ++y) {
        glm::ivec2& span = tile_span[t * kTile + size_t(y - ya)];
        for (int x = xa; x < xb; ++x) {
          const int q = (y - ya) * kTile + (x - xa);
          const size_t p = size_t(y) * size_t(size.x) + size_t(x);
          const float a = 1.0f - T[q];
          if (!(a > 0.0f) || a < s.min_coverage) {
            std::fill(&rgba[4 * p], &rgba[4 * p + 4], 0.0f);
            depth[p] = kNone;
            continue;
          }
          const vec3 straight = glm::clamp(C[q] / a, vec3(0.0f), vec3(1.0f));
          rgba[4 * p] = straight.x, rgba[4 * p + 1] = straight.y, rgba[4 * p + 2] = straight.z, rgba[4 * p + 3] = a;
          depth[p] = d[q] != kNone ? d[q] : best_depth[q];
          span = {std::min(span.x, x), std::max(span.y, x)};
        }
      }
    }
  });
  for (size_t t = 0; t < tiles; ++t) {
    const int ty = int(t / size_t(tiles_x));
    for (int k = 0; k < kTile; ++k) {
      const int y = ty * kTile + k;
      if (y >= size.y) break;
      const glm::ivec2 sp = tile_span[t * kTile + size_t(k)];
      if (sp.y < 0) continue;
      row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, sp.x), std::max(row_span[size_t(y)].y, sp.y)};
    }
  }
  const auto t3 = Clock::now();
  upload_cpu_mark(ctx.targets, clip, rgba, depth, row_span, ctx.coverage, "gaussians");
  report(t3);
  return counts;
}

}  // namespace pointnpr::gaussians
