// The stipples mark's passes on the CPU's threads (TBB), for software GL
// devices, where llvmpipe's per-texel passes and per-point atomics cost
// several times a plain loop. The per-point and per-pixel rules are
// shaders/stipples_kernels.glsl, the text the GL passes compile (so the
// same texels, cells and decisions), on the host's copy of the points:
//
//  - Point passes project each point again (a few multiplies, cheaper than
//    storing it) in work items of at most kPointGrain points; texels and cells
//    take min / max / add by atomic operations on 32-bit integers (depths
//    as their bits: positive floats order as their bits), so the result is
//    the same in whatever order the threads ran.
//  - The spreading is separable: min over the 3 x 3 neighbours plus a step
//    equals the 3 x 3 minimum (rows, then columns) plus the step, since
//    adding the step is monotonic; the paper's surface (no step) is one
//    box minimum of iterations + 1 texels; the closing's erosions one box
//    "all covered" of `iterations` texels, clamped at the window's edge as
//    the shader's.
//  - Dots are scattered into coverage and depth images over the clip, which
//    the resolve turns into colour and depth, uploaded once; it also hands
//    the renderer the covered bounds (no pass over the depth to find them).
#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/hash.h"
#include "geometry/analysis.h"
#include "gl/device.h"
#include "marks/stipples/native_parts.h"
#include "marks/stipples/stipples.h"
#include "render/gpu_cloud.h"
#include "render/native_raster.h"
#include "scene/point_cloud.h"
#include "scene/splat_attributes.h"

namespace pointnpr {
namespace stipples {
namespace {

using namespace stipples_native;

// What the shared kernels read: the settings, the window, and the pass's
// host images (set as the passes size them).
struct Kernels {
  const StippleSettings& u;
  StippleWindowSettings win{};
  const uint32_t* hp = nullptr;
  const uint32_t* quad = nullptr;
  const uint32_t* eye_count = nullptr;
  const uint32_t* eye_cover = nullptr;
  const uint32_t* light_count = nullptr;
  uint hp_at(uint i) const { return hp[i]; }
  uint quad_at(uint i) const { return quad[i]; }
  uint eye_count_at(uint i) const { return eye_count[i]; }
  uint eye_cover_at(uint i) const { return eye_cover[i]; }
  uint light_count_at(uint i) const { return light_count[i]; }
  // The kernels' floor without a library call (std::floor is one without SSE4.1).
  static float floor(float v) { return floor_f(v); }
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "stipples_kernels.glsl"
#pragma GCC diagnostic pop
};
using Pt = Kernels::Pt;
// points.glsl's and stipples.comp's kOpacitySalt: the splats the points mark draws.
constexpr uint32_t kOpacitySalt = 0x6f706163u;
using StipplePixel = Kernels::StipplePixel;

class NativeStipplePasses final : public StipplePasses {
 public:
  NativeStipplePasses(const MarkContext& ctx, const StippleSetup& s)
      : ctx_(ctx), s_(s), host_(ctx.host->get<HostBuffers>()), k_{s.u} {
    quad_ = sized(host_.quad, s.quad_n());
    fill(quad_, s.quad_n(), 0xffffffffu);
    light_count_ = sized(host_.light_count, s.light_n());
    fill(light_count_, s.light_n(), 0u);
    hist_.assign(kStippleHistogramBins, 0u);
    k_.quad = quad_;
    k_.light_count = light_count_;
  }

  void project_casters(std::span<const VisibleChunk> chunks) override {
    const PassTimer timer(ctx_.stats, "stipples_native_project_ms");
    prepare(chunks);
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      for (uint32_t i = begin; i < end; ++i) {
        const Pt p = project(c, local_index(c, i));
        if (p.in_depth) cast(p);
      }
    });
  }

  void hidden_points(const StippleWindow& w, std::span<const VisibleChunk> chunks, bool for_frame, bool casters,
                     bool surface) override {
    std::optional<PassTimer> timer(std::in_place, ctx_.stats, "stipples_native_project_ms");
    w_ = w;
    k_.win = w.k;
    visible_ = 0;
    const size_t n = w.fine_n();
    eye_n_ = s_.counts_eye() ? w.eye_n() : 1;
    eye_count_.assign(eye_n_, 0u);
    eye_cover_.assign(eye_n_, 0u);
    k_.eye_count = eye_count_.data();
    k_.eye_cover = eye_cover_.data();
    uint32_t* hp = sized(host_.hp, n);
    k_.hp = hp;
    uint32_t* tmp = sized(host_.tmp, n);
    uint32_t* surf = sized(host_.surface, n);
    fill(hp, n, kInfBits);
    fill(surf, n, kInfBits);
    prepare(chunks);
    ++window_generation_;
    window_chunks_ = chunks;
    uint32_t* point_texel = sized(host_.point_texel, points_);
    uint32_t* point_depth = sized(host_.point_depth, points_);
    const bool cast_all = casters && s_.u.quadtree && s_.u.casters_all;
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      for (uint32_t i = begin; i < end; ++i) {
        const Pt p = project(c, local_index(c, i));
        const uint32_t texel = p.inside ? k_.fine_index(p.fine) : kOutside;
        point_texel[c.slot + i] = texel;
        point_depth[c.slot + i] = bits(p.depth);
        if (p.inside) {
          // Its own spread (spread_from_spacing): a step deeper per texel, as the iterations' spreading.
          const int r = spread_of(c, local_index(c, i), p.depth);
          if (r == 0) {
            fetch_min(hp[texel], bits(p.depth));
          } else {
            for_spread(p.fine, r, [&](int x, int y, int ring) {
              fetch_min(hp[k_.fine_index(glm::ivec2(x, y))], bits(k_.spread_depth(p, ring)));
            });
          }
        }
        if (cast_all && p.in_depth) cast(p);
      }
    });
    // Each texel takes its neighbours' depths, each a step deeper.
    timer.emplace(ctx_.stats, "stipples_native_spread_ms");
    for (int it = 0; it < s_.iterations; ++it) {
      spread_step(w_.k.fine_size, s_.u.offset, hp, tmp);
      std::memcpy(hp, tmp, n * 4);
    }
    // The visible points: counted, their surface, the frame's counts.
    timer.emplace(ctx_.stats, "stipples_native_visible_ms");
    std::atomic<uint32_t> visible{0};
    const bool visible_casters = for_frame && s_.u.quadtree && !s_.u.casters_all;
    const bool projects = visible_casters || s_.counts_eye();  // else the texel and depth are all it needs
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      uint32_t owned_visible = 0;
      for (uint32_t i = begin; i < end; ++i) {
        if (!visible_slot(c.slot + i, hp)) continue;
        const uint32_t texel = point_texel[c.slot + i];
        const bool own = owned_texel(texel);
        owned_visible += own ? 1u : 0u;
        // The visible surface, spread for the paper (its own spread included, without the step).
        const int r = spread_of(c, local_index(c, i), from_bits(point_depth[c.slot + i]));
        if (r == 0) {
          fetch_min(surf[texel], point_depth[c.slot + i]);
        } else {
          const glm::ivec2 t(int(texel % uint32_t(w_.k.fine_size.x)), int(texel / uint32_t(w_.k.fine_size.x)));
          for_spread(t, r, [&](int x, int y, int) {
            fetch_min(surf[k_.fine_index(glm::ivec2(x, y))], point_depth[c.slot + i]);
          });
        }
        if (!projects) continue;
        const Pt p = project(c, local_index(c, i));
        if (visible_casters && own) cast(p);
        if (s_.counts_eye()) fetch_add(eye_count_[k_.eye_index(p.center)], 1u);
        if (s_.u.specular && for_frame && own) fetch_add(light_count_[k_.light_cell_index(p.view)], 1u);
      }
      visible.fetch_add(owned_visible, std::memory_order_relaxed);
    });
    visible_ = visible.load();
    has_surface_ = surface;
    if (surface) {
      // The surface's depth for the paper: the visible points spread one
      // texel further, without the step (a box minimum).
      timer.emplace(ctx_.stats, "stipples_native_surface_ms");
      box_min(w_.k.fine_size, surf, tmp, s_.iterations + 1);
      std::memcpy(surf, tmp, n * 4);
    }
  }

  // Covered texels per eye cell: `iterations` erosions of the spread depth
  // (each texel covered where every texel within that many, clamped to the
  // window, is), counted by the eye cell of the texel's centre.
  void cover() override {
    const PassTimer timer(ctx_.stats, "stipples_native_cover_ms");
    const glm::ivec2 size = w_.k.fine_size;
    const int k = s_.iterations;
    const uint32_t* hp = host_.hp.data();
    // The eye cell of each column's and each row's texel centres.
    std::vector<int> cell_x(size_t(size.x)), cell_y(size_t(size.y));
    for (int x = 0; x < size.x; ++x)
      cell_x[size_t(x)] = k_.eye_axis((float(x + w_.k.fine_min.x) + 0.5f) / s_.u.factor, w_.k.eye_min.x, w_.k.eye_cells.x);
    for (int y = 0; y < size.y; ++y)
      cell_y[size_t(y)] = k_.eye_axis((float(y + w_.k.fine_min.y) + 0.5f) / s_.u.factor, w_.k.eye_min.y, w_.k.eye_cells.y);
    tbb::parallel_for(tbb::blocked_range<int>(0, size.y, kRowGrain), [&](const tbb::blocked_range<int>& rows) {
      std::vector<uint8_t> column(size_t(size.x));
      for (int y = rows.begin(); y < rows.end(); ++y) {
        // Columns covered over rows [y - k, y + k] (clamped).
        const int y0 = std::max(y - k, 0), y1 = std::min(y + k, size.y - 1);
        std::fill(column.begin(), column.end(), uint8_t(1));
        for (int r = y0; r <= y1; ++r) {
          const uint32_t* line = hp + size_t(r) * size_t(size.x);
          for (int x = 0; x < size.x; ++x) column[size_t(x)] &= uint8_t(line[x] != kInfBits);
        }
        uint32_t* counts = eye_cover_.data() + size_t(cell_y[size_t(y)]) * size_t(w_.k.eye_cells.x);
        int run_cell = -1;
        uint32_t run = 0;
        for (int x = 0; x < size.x; ++x) {
          const int x0 = std::max(x - k, 0), x1 = std::min(x + k, size.x - 1);
          bool all = true;
          for (int q = x0; q <= x1 && all; ++q) all = column[size_t(q)] != 0;
          if (!all) continue;
          const int cell = cell_x[size_t(x)];
          if (cell != run_cell) {
            if (run) fetch_add(counts[run_cell], run);
            run_cell = cell;
            run = 0;
          }
          ++run;
        }
        if (run) fetch_add(counts[run_cell], run);
      }
    });
  }

  void reduce_quadtree() override {
    const PassTimer timer(ctx_.stats, "stipples_native_quadtree_ms");
    for (int l = s_.u.levels - 1; l >= 0; --l) {
      const int side = 1 << l;
      tbb::parallel_for(tbb::blocked_range<int>(0, side, 64), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
          for (int x = 0; x < side; ++x) {
            uint32_t m = 0xffffffffu;
            for (int k = 0; k < 4; ++k) m = std::min(m, quad_[k_.quad_index({2 * x + (k & 1), 2 * y + (k >> 1)}, l + 1)]);
            quad_[k_.quad_index({x, y}, l)] = m;
          }
      });
    }
  }

  void specular_histogram(std::span<const VisibleChunk> chunks) override {
    const PassTimer timer(ctx_.stats, "stipples_native_specular_ms");
    const bool cached = same_chunks(chunks);
    prepare(chunks);
    const uint32_t* hp = k_.hp = host_.hp.data();
    float* point_spec = cached ? sized(host_.point_spec, points_) : nullptr;
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      std::vector<uint32_t> local(kStippleHistogramBins, 0u);
      for (uint32_t i = begin; i < end; ++i) {
        if (cached && !visible_slot(c.slot + i, hp)) continue;
        const Pt p = project(c, local_index(c, i));
        if (!k_.hp_visible(p) || !k_.owned(p)) continue;
        const uint32_t local_i = local_index(c, i);
        const float raw = k_.specular_measure(p, c.spacing ? c.spacing[local_i] * c.spacing_cell_scale : 0.0f);
        if (point_spec) point_spec[c.slot + i] = raw;
        ++local[size_t(k_.specular_bin(raw))];
      }
      for (int b = 0; b < kStippleHistogramBins; ++b)
        if (local[size_t(b)]) fetch_add(hist_[size_t(b)], local[size_t(b)]);
    });
    spec_generation_ = cached ? window_generation_ : 0;
  }

  std::vector<uint32_t> histogram() override { return hist_; }
  void save(StippleFrameState& state) override {
    state.quad.assign(quad_, quad_ + s_.quad_n());
    state.light_count.assign(light_count_, light_count_ + s_.light_n());
  }
  void load(const StippleFrameState& state) override {
    std::copy(state.quad.begin(), state.quad.end(), quad_);
    std::copy(state.light_count.begin(), state.light_count.end(), light_count_);
  }
  uint32_t visible() override { return visible_; }

  uint32_t draw_dots(std::span<const VisibleChunk> chunks, float spec_ref,
                     std::vector<CapturedMark>* capture) override {
    const PassTimer timer(ctx_.stats, "stipples_native_dots_ms");
    const glm::ivec2 size = s_.clip.size();
    const size_t pixels = size_t(size.x) * size_t(size.y);
    uint32_t* cov = sized(host_.dot_cov, pixels);
    uint32_t* dep = sized(host_.dot_depth, pixels);
    fill(cov, pixels, 0u);
    fill(dep, pixels, kInfBits);
    const bool cached = same_chunks(chunks);
    const bool spec_cached = cached && spec_generation_ == window_generation_;
    prepare(chunks);
    if (s_.opacity_draws) attach_opacities(chunks);
    const uint32_t* hp = k_.hp = host_.hp.data();
    const float* point_spec = host_.point_spec.data();
    std::atomic<uint32_t> kept{0};
    std::vector<std::vector<CapturedMark>> captured(capture ? items_.size() : 0);
    const glm::ivec2 origin = s_.u.origin_px;
    const glm::ivec2 clip_min = s_.clip.min, clip_max = s_.clip.max;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, items_.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t it = r.begin(); it < r.end(); ++it) {
        const Item& item = items_[it];
        const HostChunk& c = host_chunks_[item.chunk];
        uint32_t item_kept = 0;
        for (uint32_t i = item.begin; i < item.end; ++i) {
          if (cached && !visible_slot(c.slot + i, hp)) continue;
          const uint32_t local = local_index(c, i);
          const Pt p = project(c, local);
          if (!k_.hp_visible(p)) continue;
          const uint32_t id = c.ids[local];
          if (c.opacity && !(glsl::id_rand(id, kOpacitySalt, 0u) < c.opacity[local])) continue;
          const float cell_target = c.spacing ? c.spacing[local] * c.spacing_cell_scale : 0.0f;
          const float lit = s_.u.diffuse ? k_.lit_scale(
                                   p, id, cell_target,
                                   c.normals ? k_.packed_view_normal(pack_normal(c.normals[local]), c.view_from_chunk)
                                             : glm::vec3(0.0f)) : 1.0f;
          if (lit <= 0.0f) continue;
          // The specular measure where the histogram took it in this window.
          if (s_.u.specular && s_.u.tau > 0.0f &&
              k_.specular_out(
                  id, spec_cached && k_.owned(p) ? point_spec[c.slot + i] : k_.specular_measure(p, cell_target),
                  spec_ref))
            continue;
          Kernels::Dot dot = k_.tone_dot(p, id);
          dot.diameter *= lit;
          if (dot.diameter <= 0.0f) continue;
          const float diameter = dot.diameter;
          ++item_kept;
          if (capture) captured[it].push_back(captured_dot(s_, p.view, id));
          const float rad = 0.5f * diameter;
          const int lo_x = std::max(int(floor_f(dot.center.x - rad - 0.5f)) - origin.x, clip_min.x);
          const int lo_y = std::max(int(floor_f(dot.center.y - rad - 0.5f)) - origin.y, clip_min.y);
          const int hi_x = std::min(int(ceil_f(dot.center.x + rad + 0.5f)) - origin.x, clip_max.x - 1);
          const int hi_y = std::min(int(ceil_f(dot.center.y + rad + 0.5f)) - origin.y, clip_max.y - 1);
          const uint32_t depth_bits = bits(p.depth);
          for (int y = lo_y; y <= hi_y; ++y)
            for (int x = lo_x; x <= hi_x; ++x) {
              const float cv = k_.dot_coverage(float(x + origin.x) + 0.5f - dot.center.x,
                                               float(y + origin.y) + 0.5f - dot.center.y, diameter);
              if (cv <= 0.0f) continue;
              const size_t pix = size_t(y - clip_min.y) * size_t(size.x) + size_t(x - clip_min.x);
              fetch_max(cov[pix], bits(cv));
              fetch_min(dep[pix], depth_bits);
            }
        }
        kept.fetch_add(item_kept, std::memory_order_relaxed);
      }
    });
    if (capture)
      for (const auto& list : captured) capture->insert(capture->end(), list.begin(), list.end());
    return kept.load();
  }

  // Dots over paper into the segment's colour and depth, uploaded over the clip.
  void resolve() override {
    std::optional<PassTimer> timer(std::in_place, ctx_.stats, "stipples_native_resolve_ms");
    const Rect clip = s_.clip;
    const glm::ivec2 size = clip.size();
    const size_t pixels = size_t(size.x) * size_t(size.y);
    float* rgba = sized(host_.rgba, 4 * pixels);
    float* depth = sized(host_.depth, pixels);
    const uint32_t* cov = host_.dot_cov.data();
    const uint32_t* dep = host_.dot_depth.data();
    const uint32_t* surf = host_.surface.data();
    // The fine texel of each column's and each row's pixel centre.
    std::vector<int> tx(size_t(size.x)), ty(size_t(size.y));
    for (int x = 0; x < size.x; ++x) tx[size_t(x)] = k_.resolve_texel(x + clip.min.x + s_.u.origin_px.x, 0);
    for (int y = 0; y < size.y; ++y) ty[size_t(y)] = k_.resolve_texel(y + clip.min.y + s_.u.origin_px.y, 1);
    std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
    tbb::parallel_for(tbb::blocked_range<int>(0, size.y, kRowGrain), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) {
        const uint32_t* surf_row = surf + size_t(ty[size_t(y)]) * size_t(w_.k.fine_size.x);
        for (int x = 0; x < size.x; ++x) {
          const size_t pix = size_t(y) * size_t(size.x) + size_t(x);
          const float surface = has_surface_ ? from_bits(surf_row[tx[size_t(x)]]) : from_bits(kInfBits);
          const StipplePixel out = k_.resolve_pixel(from_bits(cov[pix]), from_bits(dep[pix]), surface);
          std::memcpy(rgba + 4 * pix, &out.color, 16);
          depth[pix] = out.depth;
          if (out.color.w > 0.0f) row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, x), x};
        }
      }
    });
    timer.emplace(ctx_.stats, "stipples_native_upload_ms");
    upload_cpu_mark(ctx_.targets, clip, rgba, depth, row_span, ctx_.coverage, "stipples");
  }

 private:
  static void fill(uint32_t* data, size_t n, uint32_t value) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
      std::fill(data + r.begin(), data + r.end(), value);
    });
  }

  // The splats' opacities of the chunks prepare() listed, one array per cloud.
  void attach_opacities(std::span<const VisibleChunk> chunks) {
    opacities_.clear();
    const PointCloud* last = nullptr;
    for (size_t i = 0; i < chunks.size(); ++i) {
      if (clouds_[i].get() != last) {
        last = clouds_[i].get();
        opacities_.push_back(splat_opacities(*last));
      }
      host_chunks_[i].opacity = opacities_.back().data() + chunks[i].chunk->first;
    }
  }

  // The host data of `chunks` and the work items over their points.
  void prepare(std::span<const VisibleChunk> chunks) {
    points_ = 0;
    host_chunks_.clear();
    items_.clear();
    clouds_.clear();
    resolutions_.clear();
    normals_.clear();
    for (const VisibleChunk& v : chunks) {
      std::shared_ptr<const PointCloud> cloud = chunk_cloud(v, "stipples");
      HostChunk c;
      c.positions = cloud->local_positions().data() + v.chunk->first;
      c.ids = cloud->point_index().data() + v.chunk->first;
      c.count = v.chunk->count;
      if (draws_queue(v, *s_.params)) {
        c.order = v.gpu->host_queue_order().data() + v.chunk->first;
        c.count = queue_count(v, *s_.params);
      }
      c.view_from_chunk = v.view_from_chunk;
      if (s_.reads_spacing()) {
        resolutions_.push_back(cloud->analysis().surface_resolution(kStippleSpacingNeighbors));
        c.spacing = resolutions_.back()->r.data() + v.chunk->first;
        c.spacing_cell_scale = spacing_cell_scale(s_, v);
        c.spread_scale = spread_scale(s_, v);
        c.spread_cap = spread_cap(v);
      }
      if (s_.u.lit_share) {
        // The normals the GL passes read (render/gpu_cloud.cpp): the scan's own, else estimated.
        if (v.gpu->own_normals) {
          c.normals = cloud->normals().data() + v.chunk->first;
        } else {
          normals_.push_back(cloud->analysis().normals(
              {kStippleNormalNeighbors, geometry::Orientation::Consistent, {}}));
          c.normals = normals_.back()->data() + v.chunk->first;
        }
      }
      c.slot = uint32_t(points_);
      points_ += c.count;
      add_point_items(items_, uint32_t(host_chunks_.size()), c.count);
      host_chunks_.push_back(c);
      clouds_.push_back(std::move(cloud));
    }
  }

  template <class F>
  void for_points(F&& work) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, items_.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) work(host_chunks_[items_[i].chunk], items_[i].begin, items_[i].end);
    });
  }

  static uint32_t local_index(const HostChunk& c, uint32_t i) { return c.order ? c.order[i] : i; }

  // Whether a pass runs over the chunks of the last hidden_points(): then
  // the per-point arrays hold its points.
  bool same_chunks(std::span<const VisibleChunk> chunks) const {
    return chunks.data() == window_chunks_.data() && chunks.size() == window_chunks_.size();
  }
  // hp_visible() from the first projection's texel and depth.
  bool visible_slot(size_t slot, const uint32_t* hp) const {
    const uint32_t texel = host_.point_texel[slot];
    return texel != kOutside && from_bits(host_.point_depth[slot]) <= from_bits(hp[texel]) + s_.u.offset;
  }
  bool owned_texel(uint32_t texel) const {
    const glm::ivec2 t(int(texel % uint32_t(w_.k.fine_size.x)), int(texel / uint32_t(w_.k.fine_size.x)));
    return k_.owned_texel(t + w_.k.fine_min);
  }

  Pt project(const HostChunk& c, uint32_t local) const { return k_.project(c.positions[local], c.view_from_chunk); }
  // The fine texels a point covers each way (spread_texels), at its view depth.
  int spread_of(const HostChunk& c, uint32_t local, float depth) const {
    return s_.u.spread_max > 0 ? k_.spread_texels(depth, c.spacing[local], c.spread_cap, c.spread_scale) : 0;
  }
  // f(x, y, ring) over the texels of the spread r around t (in_spread; ring:
  // the Chebyshev distance), clipped to the window.
  template <class F>
  void for_spread(glm::ivec2 t, int r, F&& f) const {
    const glm::ivec2 lo = glm::max(t - r, glm::ivec2(0)), hi = glm::min(t + r, w_.k.fine_size - 1);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x)
        if (k_.in_spread(x - t.x, y - t.y, r)) f(x, y, std::max(std::abs(x - t.x), std::abs(y - t.y)));
  }
  // Into the finest level of the quadtree: the caster closest to the light.
  void cast(const Pt& p) {
    fetch_min(quad_[k_.quad_index(k_.light_texel(p.view, s_.u.levels), s_.u.levels)], k_.light_key(p.view));
  }

  const MarkContext& ctx_;
  const StippleSetup& s_;
  HostBuffers& host_;
  StippleWindow w_;
  std::vector<HostChunk> host_chunks_;
  std::vector<Item> items_;
  std::vector<std::shared_ptr<const PointCloud>> clouds_;  // held while their points are read
  std::vector<std::shared_ptr<const geometry::LocalResolution>> resolutions_;  // and their spacing
  std::vector<std::shared_ptr<const std::vector<glm::vec3>>> normals_;         // estimated normals (lit_rule share)
  std::vector<std::vector<float>> opacities_;              // attach_opacities()
  std::vector<uint32_t> hist_, eye_count_, eye_cover_;
  uint32_t* quad_ = nullptr;         // host_.quad
  uint32_t* light_count_ = nullptr;  // host_.light_count
  mutable Kernels k_;                // the shared kernels over the images above
  size_t points_ = 0;                // of the last prepare()
  std::span<const VisibleChunk> window_chunks_;
  uint64_t window_generation_ = 0, spec_generation_ = 0;
  size_t eye_n_ = 1;
  uint32_t visible_ = 0;
  bool has_surface_ = false;
};

}  // namespace
}  // namespace stipples

std::unique_ptr<StipplePasses> make_native_stipple_passes(const MarkContext& ctx, const StippleSetup& s) {
  return std::make_unique<stipples::NativeStipplePasses>(ctx, s);
}

}  // namespace pointnpr
