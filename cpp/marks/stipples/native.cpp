// The stipples mark's passes on the CPU's threads (TBB), for software GL
// devices, where llvmpipe's per-texel passes and per-point atomics cost
// several times a plain loop. The rules of shaders/stipples.comp, evaluated
// in the same float operations in the same order (so the same texels,
// cells and decisions), on the host's copy of the points:
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
#include "marks/stipples/native_parts.h"
#include "render/native_raster.h"
#include "gl/device.h"
#include "marks/stipples/stipples.h"
#include "scene/point_cloud.h"

namespace pointnpr {
namespace {

using namespace stipples_native;

class NativeStipplePasses final : public StipplePasses {
 public:
  NativeStipplePasses(const MarkContext& ctx, const StippleSetup& s)
      : ctx_(ctx), s_(s), host_(ctx.host->get<HostBuffers>()) {
    quad_ = sized(host_.quad, s.quad_n());
    fill(quad_, s.quad_n(), 0xffffffffu);
    light_count_ = sized(host_.light_count, s.light_n());
    fill(light_count_, s.light_n(), 0u);
    hist_.assign(kStippleHistogramBins, 0u);
    quad_stride_ = 2u << s.levels;
    for (int k = 0; k < 7; ++k) bin_edges_[k] = from_bits(kStippleBinEdgeBits[k]);
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
    visible_ = 0;
    const size_t n = w.fine_n();
    eye_n_ = s_.specular ? w.eye_n() : 1;
    eye_count_.assign(eye_n_, 0u);
    eye_cover_.assign(eye_n_, 0u);
    uint32_t* hp = sized(host_.hp, n);
    uint32_t* tmp = sized(host_.tmp, n);
    uint32_t* surf = sized(host_.surface, n);
    fill(hp, n, kInfBits);
    fill(surf, n, kInfBits);
    prepare(chunks);
    ++window_generation_;
    window_chunks_ = chunks;
    uint32_t* point_texel = sized(host_.point_texel, points_);
    uint32_t* point_depth = sized(host_.point_depth, points_);
    const bool cast_all = casters && s_.diffuse && s_.casters_all;
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      for (uint32_t i = begin; i < end; ++i) {
        const Pt p = project(c, local_index(c, i));
        const uint32_t texel = p.inside ? uint32_t(fine_index(p.fine)) : kOutside;
        point_texel[c.slot + i] = texel;
        point_depth[c.slot + i] = bits(p.depth);
        if (p.inside) fetch_min(hp[texel], bits(p.depth));
        if (cast_all && p.in_depth) cast(p);
      }
    });
    // Each texel takes its neighbours' depths, each a step deeper.
    timer.emplace(ctx_.stats, "stipples_native_spread_ms");
    for (int it = 0; it < s_.iterations; ++it) {
      spread_step(w_.fine, s_.offset, hp, tmp);
      std::memcpy(hp, tmp, n * 4);
    }
    // The visible points: counted, their surface, the frame's counts.
    timer.emplace(ctx_.stats, "stipples_native_visible_ms");
    std::atomic<uint32_t> visible{0};
    const bool visible_casters = for_frame && s_.diffuse && !s_.casters_all;
    const bool projects = visible_casters || s_.specular;  // else the texel and depth are all it needs
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      uint32_t owned_visible = 0;
      for (uint32_t i = begin; i < end; ++i) {
        if (!visible_slot(c.slot + i, hp)) continue;
        const uint32_t texel = point_texel[c.slot + i];
        const bool own = owned_texel(texel);
        owned_visible += own ? 1u : 0u;
        fetch_min(surf[texel], point_depth[c.slot + i]);
        if (!projects) continue;
        const Pt p = project(c, local_index(c, i));
        if (visible_casters && own) cast(p);
        if (s_.specular) {
          fetch_add(eye_count_[eye_index(p.center)], 1u);
          if (for_frame && own) fetch_add(light_count_[light_cell_index(p.view)], 1u);
        }
      }
      visible.fetch_add(owned_visible, std::memory_order_relaxed);
    });
    visible_ = visible.load();
    has_surface_ = surface;
    if (surface) {
      // The surface's depth for the paper: the visible points spread one
      // texel further, without the step (a box minimum).
      timer.emplace(ctx_.stats, "stipples_native_surface_ms");
      box_min(w_.fine, surf, tmp, s_.iterations + 1);
      std::memcpy(surf, tmp, n * 4);
    }
  }

  // Covered texels per eye cell: `iterations` erosions of the spread depth
  // (each texel covered where every texel within that many, clamped to the
  // window, is), counted by the eye cell of the texel's centre.
  void cover() override {
    const PassTimer timer(ctx_.stats, "stipples_native_cover_ms");
    const glm::ivec2 size = w_.fine;
    const int k = s_.iterations;
    const uint32_t* hp = host_.hp.data();
    // The eye cell of each column's and each row's texel centres.
    std::vector<int> cell_x(size_t(size.x)), cell_y(size_t(size.y));
    for (int x = 0; x < size.x; ++x)
      cell_x[size_t(x)] = eye_axis((float(x + w_.fine_min.x) + 0.5f) / s_.factor, 0);
    for (int y = 0; y < size.y; ++y)
      cell_y[size_t(y)] = eye_axis((float(y + w_.fine_min.y) + 0.5f) / s_.factor, 1);
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
        uint32_t* counts = eye_cover_.data() + size_t(cell_y[size_t(y)]) * size_t(w_.eye_cells.x);
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
    for (int l = s_.levels - 1; l >= 0; --l) {
      const int side = 1 << l;
      tbb::parallel_for(tbb::blocked_range<int>(0, side, 64), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
          for (int x = 0; x < side; ++x) {
            uint32_t m = 0xffffffffu;
            for (int k = 0; k < 4; ++k) m = std::min(m, quad_[quad_index({2 * x + (k & 1), 2 * y + (k >> 1)}, l + 1)]);
            quad_[quad_index({x, y}, l)] = m;
          }
      });
    }
  }

  void specular_histogram(std::span<const VisibleChunk> chunks) override {
    const PassTimer timer(ctx_.stats, "stipples_native_specular_ms");
    const bool cached = same_chunks(chunks);
    prepare(chunks);
    const uint32_t* hp = host_.hp.data();
    float* point_spec = cached ? sized(host_.point_spec, points_) : nullptr;
    for_points([&](const HostChunk& c, uint32_t begin, uint32_t end) {
      std::vector<uint32_t> local(kStippleHistogramBins, 0u);
      for (uint32_t i = begin; i < end; ++i) {
        if (cached && !visible_slot(c.slot + i, hp)) continue;
        const Pt p = project(c, local_index(c, i));
        if (!hp_visible(p, hp) || !owned(p)) continue;
        const float raw = specular_raw(p);
        if (point_spec) point_spec[c.slot + i] = raw;
        ++local[size_t(histogram_bin(raw))];
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
    const uint32_t* hp = host_.hp.data();
    const float* point_spec = host_.point_spec.data();
    std::atomic<uint32_t> kept{0};
    std::vector<std::vector<CapturedMark>> captured(capture ? items_.size() : 0);
    const glm::ivec2 origin = s_.origin_px;
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
          if (!hp_visible(p, hp)) continue;
          const uint32_t id = c.ids[local];
          if (s_.diffuse) {
            // Fractional LEVEL: the finer level with probability frac.
            const int level = s_.level_lo + (hash01(id, 1u) < s_.level_frac ? 1 : 0);
            const glm::ivec2 t = light_texel(p.view, s_.levels) >> (s_.levels - level);
            if (quad_[quad_index(t, level)] == order_key(-dot3(p.view, s_.light_dir))) continue;
          }
          if (s_.specular && s_.tau > 0.0f) {
            // The histogram's value where it measured this point in this window.
            const float raw = spec_cached && owned(p) ? point_spec[c.slot + i] : specular_raw(p);
            const float diff = 1.0f - raw / spec_ref;
            if (diff < s_.tau * hash01(id, 2u)) continue;  // hidden with probability 1 - diff / tau
          }
          ++item_kept;
          if (capture) captured[it].push_back(captured_dot(s_, p.view, id));
          // 1 + jitter * (2h - 1), written as the GL compiler (NIR) reassociates it,
          // so both implementations round alike; the shader spells it the same.
          const float diameter = std::max(
              s_.dot_size * ((1.0f - s_.size_jitter) + 2.0f * s_.size_jitter * hash01(id, 3u)), 0.5f);
          const float rad = 0.5f * diameter;
          const int lo_x = std::max(int(floor_f(p.center.x - rad - 0.5f)) - origin.x, clip_min.x);
          const int lo_y = std::max(int(floor_f(p.center.y - rad - 0.5f)) - origin.y, clip_min.y);
          const int hi_x = std::min(int(ceil_f(p.center.x + rad + 0.5f)) - origin.x, clip_max.x - 1);
          const int hi_y = std::min(int(ceil_f(p.center.y + rad + 0.5f)) - origin.y, clip_max.y - 1);
          const uint32_t depth_bits = bits(p.depth);
          const float small = std::min(1.0f, diameter * diameter);
          const float reach = rad + 0.5f;
          // Beyond this squared distance the coverage is 0 (sqrt is
          // monotonic and correctly rounded; the margin covers its rounding).
          const float outside = reach * reach * 1.0001f;
          for (int y = lo_y; y <= hi_y; ++y)
            for (int x = lo_x; x <= hi_x; ++x) {
              // Area coverage of a disc (1 px wide antialiased edge, at least a
              // pixel's worth spread over the pixels a small dot touches).
              const float dx = float(x + origin.x) + 0.5f - p.center.x;
              const float dy = float(y + origin.y) + 0.5f - p.center.y;
              const float d2 = dx * dx + dy * dy;
              if (d2 > outside) continue;
              const float dist = std::sqrt(d2);
              const float cv = std::clamp(reach - dist, 0.0f, 1.0f) * small;
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
    const glm::vec4 ink_color = s_.dot_color, paper_color = s_.paper;
    // The fine texel of each column's and each row's pixel centre.
    std::vector<int> tx(size_t(size.x)), ty(size_t(size.y));
    for (int x = 0; x < size.x; ++x)
      tx[size_t(x)] = std::clamp(int(floor_f((float(x + clip.min.x + s_.origin_px.x) + 0.5f) * s_.factor)) -
                                     w_.fine_min.x, 0, w_.fine.x - 1);
    for (int y = 0; y < size.y; ++y)
      ty[size_t(y)] = std::clamp(int(floor_f((float(y + clip.min.y + s_.origin_px.y) + 0.5f) * s_.factor)) -
                                     w_.fine_min.y, 0, w_.fine.y - 1);
    std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
    tbb::parallel_for(tbb::blocked_range<int>(0, size.y, kRowGrain), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) {
        const uint32_t* surf_row = surf + size_t(ty[size_t(y)]) * size_t(w_.fine.x);
        for (int x = 0; x < size.x; ++x) {
          const size_t pix = size_t(y) * size_t(size.x) + size_t(x);
          const float surface = has_surface_ ? from_bits(surf_row[tx[size_t(x)]]) : from_bits(kInfBits);
          const bool on_surface = !std::isinf(surface) && paper_color.a > 0.0f;
          const float ink = from_bits(cov[pix]) * ink_color.a;
          const float paper = on_surface ? paper_color.a : 0.0f;
          const float alpha = ink + paper * (1.0f - ink);
          float* out = rgba + 4 * pix;
          if (alpha > 0.0f) {
            for (int k = 0; k < 3; ++k)
              out[k] = std::clamp((ink_color[k] * ink + paper_color[k] * paper * (1.0f - ink)) / alpha, 0.0f, 1.0f);
            out[3] = alpha;
            const float dot_d = from_bits(dep[pix]);
            depth[pix] = ink > 0.0f ? std::min(dot_d, on_surface ? surface : from_bits(kInfBits)) : surface;
            row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, x), x};
          } else {
            out[0] = out[1] = out[2] = out[3] = 0.0f;
            depth[pix] = from_bits(kInfBits);
          }
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

  // The host data of `chunks` and the work items over their points.
  void prepare(std::span<const VisibleChunk> chunks) {
    points_ = 0;
    host_chunks_.clear();
    items_.clear();
    clouds_.clear();
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
    return texel != kOutside && from_bits(host_.point_depth[slot]) <= from_bits(hp[texel]) + s_.offset;
  }
  bool owned_texel(uint32_t texel) const {
    const glm::ivec2 t(int(texel % uint32_t(w_.fine.x)), int(texel / uint32_t(w_.fine.x)));
    return owned_fine(t + w_.fine_min);
  }

  Pt project(const HostChunk& c, uint32_t local) const {
    Pt p;
    p.view = affine(c.view_from_chunk, c.positions[local]);
    p.depth = -p.view.z;
    const glm::mat4& m = s_.projection;
    const float cx = m[0][0] * p.view.x + m[1][0] * p.view.y + m[2][0] * p.view.z + m[3][0];
    const float cy = m[0][1] * p.view.x + m[1][1] * p.view.y + m[2][1] * p.view.z + m[3][1];
    const float cw = m[0][3] * p.view.x + m[1][3] * p.view.y + m[2][3] * p.view.z + m[3][3];
    p.center = {(cx / cw * 0.5f + 0.5f) * float(s_.frame_px.x), (cy / cw * 0.5f + 0.5f) * float(s_.frame_px.y)};
    p.in_depth = p.depth >= s_.near && p.depth <= s_.far;
    const float fx = floor_f(p.center.x * s_.factor) - float(w_.fine_min.x);
    const float fy = floor_f(p.center.y * s_.factor) - float(w_.fine_min.y);
    p.inside = p.in_depth && cw > 0.0f && fx >= 0.0f && fy >= 0.0f && fx < float(w_.fine.x) && fy < float(w_.fine.y);
    p.fine = p.inside ? glm::ivec2(int(fx), int(fy)) : glm::ivec2(0);
    return p;
  }

  size_t fine_index(glm::ivec2 t) const { return size_t(t.y) * size_t(w_.fine.x) + size_t(t.x); }
  bool owned(const Pt& p) const { return owned_fine(p.fine + w_.fine_min); }
  bool owned_fine(glm::ivec2 t) const {
    return t.x >= w_.owned_min.x && t.y >= w_.owned_min.y && t.x < w_.owned_max.x && t.y < w_.owned_max.y;
  }
  // Not behind the spread surface: within one step of its texel's depth.
  bool hp_visible(const Pt& p, const uint32_t* hp) const {
    return p.inside && p.depth <= from_bits(hp[fine_index(p.fine)]) + s_.offset;
  }

  glm::vec2 light_uv(const glm::vec3& v) const {
    return {(dot3(v, s_.light_right) - s_.light_origin.x) / s_.light_extent,
            (dot3(v, s_.light_up) - s_.light_origin.y) / s_.light_extent};
  }
  glm::ivec2 light_texel(const glm::vec3& v, int level) const {
    const int side = 1 << level;
    const glm::vec2 uv = light_uv(v);
    return {floor_clamped(uv.x * float(side), 0, side - 1), floor_clamped(uv.y * float(side), 0, side - 1)};
  }
  size_t quad_index(glm::ivec2 t, int level) const {
    const int x0 = int(quad_stride_) - (2 << level);
    return size_t(t.y) * quad_stride_ + size_t(x0 + t.x);
  }
  // Into the finest level of the quadtree: the caster closest to the light.
  void cast(const Pt& p) {
    fetch_min(quad_[quad_index(light_texel(p.view, s_.levels), s_.levels)], order_key(-dot3(p.view, s_.light_dir)));
  }

  // The eye cell (one axis) of a position in frame pixels: floor(pixel / cell) - eye_min, clamped.
  int eye_axis(float pixel, int axis) const {
    return floor_clamped(floor_f(pixel / s_.eye_cell) - float(w_.eye_min[axis]), 0, w_.eye_cells[axis] - 1);
  }
  size_t eye_index(glm::vec2 center) const {
    return size_t(eye_axis(center.y, 1)) * size_t(w_.eye_cells.x) + size_t(eye_axis(center.x, 0));
  }
  size_t light_cell_index(const glm::vec3& v) const {
    const glm::vec2 uv = light_uv(v);
    const int n = s_.light_cells;
    return size_t(floor_clamped(uv.y * float(n), 0, n - 1)) * size_t(n) + size_t(floor_clamped(uv.x * float(n), 0, n - 1));
  }

  static float overlap(float c, float lo, float hi) { return std::clamp(std::min(c + 1.0f, hi) - std::max(c, lo), 0.0f, 1.0f); }

  // The shader's specular_raw: area per point seen from the eye and from the light.
  float specular_raw(const Pt& p) const {
    const glm::vec2 e(p.center.x / s_.eye_cell - float(w_.eye_min.x), p.center.y / s_.eye_cell - float(w_.eye_min.y));
    float points = 0.0f, covered = 0.0f;
    const glm::ivec2 e0(int(floor_f(e.x - 1.5f)), int(floor_f(e.y - 1.5f)));
    // Each cell's weight is the product of its overlaps along x and y.
    float ox[4], oy[4];
    for (int k = 0; k <= 3; ++k) {
      ox[k] = overlap(float(e0.x + k), e.x - 1.5f, e.x + 1.5f);
      oy[k] = overlap(float(e0.y + k), e.y - 1.5f, e.y + 1.5f);
    }
    for (int dy = 0; dy <= 3; ++dy)
      for (int dx = 0; dx <= 3; ++dx) {
        const glm::ivec2 c = e0 + glm::ivec2(dx, dy);
        if (c.x < 0 || c.y < 0 || c.x >= w_.eye_cells.x || c.y >= w_.eye_cells.y) continue;
        const float w = ox[dx] * oy[dy];
        const size_t i = size_t(c.y) * size_t(w_.eye_cells.x) + size_t(c.x);
        points += w * float(eye_count_[i]);
        covered += w * float(eye_cover_[i]);
      }
    const float wd = s_.ortho ? 1.0f : p.depth;
    const float px_area = wd / s_.px_per_unit;
    const float eye_area = covered / (s_.factor * s_.factor) * px_area * px_area / std::max(points, 1.0f);
    const glm::vec2 uv = light_uv(p.view);
    const glm::vec2 l = uv * float(s_.light_cells);
    float lpoints = 0.0f, occupied = 0.0f;
    const glm::ivec2 l0(int(floor_f(l.x - 1.5f)), int(floor_f(l.y - 1.5f)));
    for (int k = 0; k <= 3; ++k) {
      ox[k] = overlap(float(l0.x + k), l.x - 1.5f, l.x + 1.5f);
      oy[k] = overlap(float(l0.y + k), l.y - 1.5f, l.y + 1.5f);
    }
    for (int dy = 0; dy <= 3; ++dy)
      for (int dx = 0; dx <= 3; ++dx) {
        const glm::ivec2 c = l0 + glm::ivec2(dx, dy);
        if (c.x < 0 || c.y < 0 || c.x >= s_.light_cells || c.y >= s_.light_cells) continue;
        const float w = ox[dx] * oy[dy];
        const uint32_t n = light_count_[size_t(c.y) * size_t(s_.light_cells) + size_t(c.x)];
        lpoints += w * float(n);
        occupied += n > 0u ? w : 0.0f;
      }
    const float cell = s_.light_extent / float(s_.light_cells);
    const float light_area = occupied * cell * cell / std::max(lpoints, 1.0f);
    return eye_area + light_area;
  }

  // 8 bins per octave of 2^-64 .. 2^64 (the shader's specular_bin): the
  // octave from the exponent, the bin within it by the mantissa against
  // 2^(k/8), exact in both.
  int histogram_bin(float s) const {
    s = std::max(s, 1e-30f);
    const uint32_t b = bits(s);
    const int octave = int(b >> 23) - 127;
    const float mantissa = from_bits((b & 0x007fffffu) | 0x3f800000u);
    int within = 0;
    for (float edge : bin_edges_) within += mantissa >= edge ? 1 : 0;
    return std::clamp((octave + 64) * 8 + within, 0, kStippleHistogramBins - 1);
  }

  float hash01(uint32_t id, uint32_t salt) const { return id_rand(id, salt, s_.seed); }

  const MarkContext& ctx_;
  const StippleSetup& s_;
  HostBuffers& host_;
  StippleWindow w_;
  std::vector<HostChunk> host_chunks_;
  std::vector<Item> items_;
  std::vector<std::shared_ptr<const PointCloud>> clouds_;  // held while their points are read
  std::vector<uint32_t> hist_, eye_count_, eye_cover_;
  uint32_t* quad_ = nullptr;         // host_.quad
  uint32_t* light_count_ = nullptr;  // host_.light_count
  size_t points_ = 0;                // of the last prepare()
  std::span<const VisibleChunk> window_chunks_;
  uint64_t window_generation_ = 0, spec_generation_ = 0;
  size_t quad_stride_ = 2;
  size_t eye_n_ = 1;
  uint32_t visible_ = 0;
  bool has_surface_ = false;
  float bin_edges_[7]{};
};

}  // namespace

std::unique_ptr<StipplePasses> make_native_stipple_passes(const MarkContext& ctx, const StippleSetup& s) {
  return std::make_unique<NativeStipplePasses>(ctx, s);
}

}  // namespace pointnpr
