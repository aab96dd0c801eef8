// The feature_strokes mark's native path: its GL passes (feature_strokes_
// depth.vert/.frag, feature_strokes_select.comp, feature_strokes.vert/.frag,
// ink_resolve.comp) on the CPU's threads (TBB), for software GL devices,
// where llvmpipe spends most of the mark's time setting up and shading
// millions of tiny primitives one pass after another.
//
//  1. Visibility discs: every point's disc scattered into a per-pixel
//     atomic minimum of (reversed depth bits inverted << 32 | point key):
//     the GL's GREATER depth test, ties to the first point drawn.
//  2. Selection: the queue's first points of each chunk classified as the
//     compute pass does, kept in queue order (work items of fixed ranges,
//     concatenated in order).
//  3. Primitives: each record's screen quad (corners on the 1/256 grid of
//     render/exact_raster.h, two triangles with a fill rule on exact
//     integer edge functions), binned by screen tiles in primitive order;
//     each tile's pixels blend their primitives in that order (colour sum,
//     transmittance product, depth minimum), the GL's blending order.
//  4. Resolve: ink over paper and the surface's depth, uploaded.
// Every value a pixel sees is computed from its frame pixel, so a tile of
// a frame is that frame's bytes, in any process and with any thread count.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/hash.h"
#include "geometry/analysis.h"
#include "gl/device.h"
#include "marks/feature_strokes/feature_strokes.h"
#include "marks/points/points.h"
#include "render/native_ink.h"
#include "render/gpu_cloud.h"
#include "render/native_raster.h"
#include "render/point_color.h"
#include "render/screen_bins.h"
#include "scene/camera.h"
#include "scene/point_cloud.h"
#include "scene/splat_attributes.h"

namespace pointnpr {

std::shared_ptr<const std::vector<uint32_t>> FeatureLineHostCache::get(const VisibleChunk& v, AttributeKey key) {
  const std::shared_ptr<const PointCloud> cloud = v.gpu->source.lock();
  const gl::Buffer* buffer = v.gpu->find(key);
  if (!cloud || !buffer) return nullptr;
  std::lock_guard lock(mutex_);
  for (auto it = entries_.begin(); it != entries_.end();)
    it = it->second.cloud.expired() ? entries_.erase(it) : std::next(it);
  Entry& e = entries_[cloud->id()];
  if (e.lines && e.key == key) return e.lines;
  auto lines = std::make_shared<std::vector<uint32_t>>(3 * cloud->size());  // line, link, length
  glGetNamedBufferSubData(buffer->id(), 0, GLsizeiptr(lines->size() * sizeof(uint32_t)), lines->data());
  gl::check_gl("feature strokes: reading the line fits back");
  e = Entry{cloud, key, lines};
  return lines;
}

namespace {

constexpr uint64_t kEmpty = ~uint64_t(0);
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint32_t kBatchRecords = 1u << 18;  // as the GL path's batches

using namespace feature_strokes;
#include "feature_strokes_disc.glsl"

// One visible chunk's host data (index = first + local into the cloud's arrays).
struct Chunk {
  const glm::vec3* positions = nullptr;
  const uint32_t* ids = nullptr;
  const float* degree = nullptr;
  const float* resolution = nullptr;
  const uint32_t* lines = nullptr;  // or null: no line fit; 3 words a point (FeatureLine)
  const uint32_t* order = nullptr;  // the queue order (chunk-local), or null
  const float* opacity = nullptr;   // opacity_draws: the splats' opacities, or null
  HostColors colors;
  const glm::vec3* normals = nullptr;  // or null: not lit (shading)
  const glm::vec3* disc_normals = nullptr;  // the visibility discs' planes
  glm::mat3 normal_matrix{1.0f};
  uint32_t first = 0, count = 0, drawn = 0, visited = 0, key_base = 0;
  float inv_median_r = 1.0f;
  float max_r = std::numeric_limits<float>::infinity();
  glm::mat4 view{1.0f};
};

struct Frame {
  glm::vec2 size{0.0f};     // the whole frame's
  glm::ivec2 origin{0, 0};  // the tile's
  Rect clip;                // tile pixels
  float near = 0.0f, far = 1.0f;
  bool ortho = false;
  float px_per_unit = 1.0f;
  glm::mat4 projection{1.0f};
};

float reversed_z(const Frame& f, float depth) {
  return f.ortho ? 1.0f - (depth - f.near) / (f.far - f.near) : f.near / depth;
}

// Pass 1 (feature_strokes_depth.vert/.frag): points [begin, end) of a chunk.
void scatter_discs(const Chunk& c, const Frame& f, const FeatureStrokeSettings& s, uint64_t* keys, uint32_t begin,
                   uint32_t end) {
  const int stride = f.clip.size().x;
  const float reach = 0.5f * kMaxDiscPixels + 1.0f;
  const float lo_x = float(f.clip.min.x + f.origin.x) - reach, hi_x = float(f.clip.max.x + f.origin.x) + reach;
  const float lo_y = float(f.clip.min.y + f.origin.y) - reach, hi_y = float(f.clip.max.y + f.origin.y) + reach;
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t index = c.first + i;
    const glm::vec4 v = transform(c.view, c.positions[index]);
    const float depth = -v.z;
    if (!(depth >= f.near && depth <= f.far)) continue;
    float r = c.resolution[index];
    if (!(r == r) || r < 0.0f) r = 0.0f;
    r = std::min(r, c.max_r);
    const float w = f.ortho ? 1.0f : depth;
    const float diameter = std::clamp(s.disc_scale * r * f.px_per_unit / std::max(w, 1e-30f), 1.0f, kMaxDiscPixels);
    const glm::vec4 clip = transform(f.projection, v);
    const float fx = (clip.x / clip.w * 0.5f + 0.5f) * f.size.x;
    const float fy = (clip.y / clip.w * 0.5f + 0.5f) * f.size.y;
    if (!(fx >= lo_x && fx <= hi_x && fy >= lo_y && fy <= hi_y)) continue;  // also NaN
    const float pushed = depth + s.depth_offset * r;
    const float z = std::max(reversed_z(f, pushed), 0.0f);
    if (!(z > 0.0f)) continue;  // the GREATER test against the cleared far end
    // The window position on the 1/256 grid, less the tile's origin (exact).
    const float wx = float(round_even(fx * 256.0f)) / 256.0f - float(f.origin.x);
    const float wy = float(round_even(fy * 256.0f)) / 256.0f - float(f.origin.y);
    // point_attributes.glsl's view_normal() of the normal as uploaded (snorm8).
    const glm::vec3 n = unit_or_zero(c.normal_matrix * unpack_normal(pack_normal(c.disc_normals[index])));
    const vec3 shape = disc_shape(n, glm::vec3(v), f.ortho);
    const float rad = 0.5f * diameter;
    const int x0 = std::max(floor_int(wx - rad), f.clip.min.x);
    const int x1 = std::min(ceil_int(wx + rad), f.clip.max.x - 1);
    const int y0 = std::max(floor_int(wy - rad), f.clip.min.y);
    const int y1 = std::min(ceil_int(wy + rad), f.clip.max.y - 1);
    uint32_t z_bits;
    std::memcpy(&z_bits, &z, 4);
    const uint64_t packed = uint64_t(~z_bits) << 32 | uint64_t(c.key_base + i);
    for (int y = y0; y <= y1; ++y) {
      const float dy = float(y) + 0.5f - wy;
      uint64_t* line = keys + size_t(y - f.clip.min.y) * size_t(stride) - f.clip.min.x;
      for (int x = x0; x <= x1; ++x) {
        const float dx = float(x) + 0.5f - wx;
        // The point's square, and the disc from 2 px on (the shader's discard).
        const bool in = diameter >= 2.0f ? on_disc(vec2(dx, dy), diameter, shape)
                                         : std::abs(dx) <= rad && std::abs(dy) <= rad;
        if (in) fetch_min(line[x], packed);
      }
    }
  }
}

// What the kernels read of a chunk's points (the select pass's buffers)
// and of the stroke texture.
struct Kernels {
  const FeatureStrokesSettings& u;
  const Chunk* chunk_;  // (names the kernels do not use)
  const HostTexture* image_;
  float point_degree(uint index) const { return chunk_->degree[index]; }
  bool has_lines() const { return chunk_->lines != nullptr; }
  uint point_line(uint index) const { return chunk_->lines[3 * size_t(index)]; }
  uint point_link(uint index) const { return chunk_->lines[3 * size_t(index) + 1]; }
  float point_link_length(uint index) const { return uintBitsToFloat(chunk_->lines[3 * size_t(index) + 2]); }
  float point_resolution(uint index) const { return chunk_->resolution[index]; }
  float inv_median_r() const { return chunk_->inv_median_r; }
  float max_r() const { return chunk_->max_r; }
  bool has_color() const { return chunk_->colors.source != ColorSource::Constant; }
  vec4 point_color(uint index) const { return chunk_->colors.at(index); }
  mat3 view_rotation() const { return mat3(chunk_->view); }
  bool lit() const { return chunk_->normals != nullptr; }
  // point_attributes.glsl's view_normal() of the normal as uploaded (snorm8).
  vec3 point_normal(uint index) const {
    return unit_or_zero(chunk_->normal_matrix * unpack_normal(pack_normal(chunk_->normals[index])));
  }
  bool has_opacity() const { return chunk_->opacity != nullptr; }
  float point_opacity(uint index) const { return chunk_->opacity[index]; }
  vec4 stroke_image(vec2 uv) const { return image_->sample(uv.x, uv.y); }
#include "feature_strokes_kernels.glsl"
#include "feature_strokes_sprite.glsl"
};

// Pass 2a (feature_strokes_select.comp): queue points [begin, end), kept in
// order; past the queue's drawn points, only chain links.
void select_records(Kernels k, uint32_t begin, uint32_t end, std::vector<Record>& out) {
  const Chunk& c = *k.chunk_;
  for (uint32_t j = begin; j < end; ++j) {
    const uint32_t index = c.first + (c.order ? c.order[j] : j);
    const Record rec = k.place_record(index, c.ids[index], mat_vec(c.view, vec4(c.positions[index], 1.0f)), j < c.drawn);
    if (rec.primitive != 0u) out.push_back(rec);
  }
}

// A primitive as the rasterizer sees it (feature_strokes.vert's outputs).
struct Prim {
  StrokeSprite sprite;
  ExactQuad quad;
};

// feature_strokes.vert: false when nothing of it reaches the clip.
bool setup(Kernels& k, const Record& rec, const Frame& f, Prim& p) {
  p.sprite = k.stroke_sprite(rec);
  const vec2 center = p.sprite.center;
  const float reach = p.sprite.size.x + p.sprite.size.y + 2.0f;
  const float lo_x = float(f.clip.min.x + f.origin.x) - reach, hi_x = float(f.clip.max.x + f.origin.x) + reach;
  const float lo_y = float(f.clip.min.y + f.origin.y) - reach, hi_y = float(f.clip.max.y + f.origin.y) + reach;
  if (!(center.x >= lo_x && center.x <= hi_x && center.y >= lo_y && center.y <= hi_y)) return false;
  const vec2 corners[4] = {k.sprite_corner(p.sprite, vec2(0.0f, 0.0f)), k.sprite_corner(p.sprite, vec2(1.0f, 0.0f)),
                           k.sprite_corner(p.sprite, vec2(1.0f, 1.0f)), k.sprite_corner(p.sprite, vec2(0.0f, 1.0f))};
  return exact_quad(corners, f.origin, f.clip, p.quad);
}

// Pass 2b: primitive p over the pixels of `area` (feature_strokes.frag and
// the ink layer's blending), against the discs' keys.
void rasterize(Kernels& k, const Prim& p, const Rect& area, const Frame& f, const HostInk& ink,
               const uint64_t* keys) {
  for_each_covered_pixel(p.quad, area, f.origin, [&](int x, int y) {
    const size_t q = ink.at(x, y);
    // GEQUAL against the discs' reversed depth (none: the far end, 0).
    const uint64_t key = keys[q];
    if (key != kEmpty && !(p.sprite.z >= glsl::uintBitsToFloat(~uint32_t(key >> 32)))) return;
    const float a = k.sprite_alpha(p.sprite, vec2(float(x + f.origin.x) + 0.5f, float(y + f.origin.y) + 0.5f));
    if (a > 0.0f) ink.blend(q, vec3(p.sprite.color), a, p.sprite.depth);
  });
}

// The host images of the last frames, kept by the renderer (HostScratch) so
// a frame does not page-fault them in anew (bounded by the largest clip, a
// tile's region at most).
struct HostImages {
  std::vector<uint64_t> keys;
  HostInkImages ink;
  size_t bytes() const { return held_bytes(keys) + ink.bytes(); }
};

// Binned pass 2b of one batch of primitives, in their order per pixel.
void draw_primitives(const Kernels& kernels, const std::vector<Prim>& prims, const Frame& f, const HostInk& ink,
                     const uint64_t* keys) {
  auto bounds = [&](size_t i, glm::ivec2& lo, glm::ivec2& hi) {
    lo = prims[i].quad.lo;
    hi = prims[i].quad.hi;
    return true;
  };
  for_each_bin_in_order(prims.size(), f.clip, bounds, [&](const Rect& area, const uint32_t* list, size_t n) {
    Kernels k = kernels;
    for (size_t j = 0; j < n; ++j) rasterize(k, prims[list[j]], area, f, ink, keys);
  });
}

}  // namespace

void draw_feature_strokes_native(const MarkContext& ctx, const FeatureStrokeSettings& s,
                                 FeatureLineHostCache& line_cache) {
  const Rect clip = ctx.clip;
  const Camera& cam = *ctx.camera;
  uint32_t counts[3] = {0, 0, 0};
  double queued = 0.0;
  for (uint32_t n : s.drawn) queued += double(n);
  auto report = [&] {
    if (!ctx.stats) return;
    (*ctx.stats)["strokes_drawn"] += double(counts[0]) + double(counts[1]) + double(counts[2]);
    (*ctx.stats)["strokes_directional"] += double(counts[0]);
    (*ctx.stats)["strokes_non_directional"] += double(counts[1]);
    (*ctx.stats)["strokes_dithering"] += double(counts[2]);
    (*ctx.stats)["queue_points"] += queued;
  };
  if (clip.empty()) {
    if (ctx.coverage) *ctx.coverage = Rect{};
    report();
    return;
  }
  const glm::ivec2 frame_px = frame_size(ctx.targets);
  Frame f;
  f.size = glm::vec2(frame_px);
  f.origin = ctx.targets.origin;
  f.clip = clip;
  f.near = float(cam.clip_start);
  f.far = float(cam.clip_end);
  f.ortho = cam.orthographic;
  f.px_per_unit = float(cam.pixels_per_unit(1.0, frame_px.y));
  f.projection = glm::mat4(cam.projection);

  // Host data of every chunk, held while drawing.
  std::vector<Chunk> chunks(ctx.chunks.size());
  std::vector<std::shared_ptr<const void>> held;
  const PointCloud* last = nullptr;
  Chunk proto;
  for (size_t i = 0; i < ctx.chunks.size(); ++i) {
    const VisibleChunk& v = ctx.chunks[i];
    std::shared_ptr<const PointCloud> cloud = chunk_cloud(v, "feature strokes");
    if (cloud.get() != last) {
      last = cloud.get();
      const FeatureDegreeSpec spec = feature_degree_spec(s.degree_key);
      auto degree = cloud->analysis().feature_degree(spec.neighbors, {spec.color_weight});
      auto resolution = cloud->analysis().surface_resolution(kStrokeResolutionNeighbors);
      std::shared_ptr<const std::vector<uint32_t>> lines = s.u.use_lines ? line_cache.get(v, s.line_key) : nullptr;
      proto = Chunk{};
      proto.positions = cloud->local_positions().data();
      proto.ids = cloud->point_index().data();
      proto.degree = degree->data();
      proto.resolution = resolution->r.data();
      proto.lines = lines ? lines->data() : nullptr;
      proto.order = s.queue ? v.gpu->host_queue_order().data() : nullptr;
      proto.colors = host_colors(*v.gpu, *cloud, s.color_source, s.u.constant_color);
      if (v.gpu->own_normals) {
        proto.disc_normals = cloud->normals().data();
      } else {
        auto normals = cloud->analysis().normals({s.feature_k, geometry::Orientation::Consistent, {}});
        proto.disc_normals = normals->data();
        held.push_back(normals);
      }
      if (s.lit && lit_by_shading(*s.params, proto.colors.source)) proto.normals = proto.disc_normals;
      if (s.opacity_draws) {
        auto opacity = std::make_shared<const std::vector<float>>(splat_opacities(*cloud));
        proto.opacity = opacity->data();
        held.push_back(opacity);
      }
      held.push_back(cloud);
      held.push_back(degree);
      held.push_back(resolution);
      held.push_back(lines);
    }
    Chunk& c = chunks[i];
    c = proto;
    if (c.order) c.order += v.chunk->first;
    c.first = v.chunk->first;
    c.count = v.chunk->count;
    c.drawn = s.drawn[i];
    c.visited = s.visited[i];
    c.key_base = v.key_base;
    c.inv_median_r = s.inv_median_r[i];
    c.max_r = s.max_r[i];
    c.view = v.view_from_chunk;
    c.normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_chunk)));
  }

  HostTexture image;
  if (s.u.stroke_texture == 3 && s.texture_image) image = HostTexture(*s.texture_image, "feature strokes");
  const Kernels kernels{s.u, nullptr, &image};

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const glm::ivec2 size = clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  HostImages& host = ctx.host->get<HostImages>();
  if (host.keys.size() < pixels) host.keys.resize(pixels);
  uint64_t* keys = host.keys.data();
  const HostInk ink = host.ink.clear(clip);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(keys + r.begin(), keys + r.end(), kEmpty);
  });

  // 1. Visibility discs: every point of every chunk.
  std::vector<PointItem> items;
  for (size_t i = 0; i < chunks.size(); ++i) add_point_items(items, uint32_t(i), chunks[i].count);
  for_each_point_item(items, [&](const PointItem& item) {
    scatter_discs(chunks[item.chunk], f, s, keys, item.begin, item.end);
  });
  const auto t1 = Clock::now();

  // 2. Per batch of chunks (as the GL path's): selection, then primitives.
  std::vector<Record> records;
  std::vector<Prim> prims;
  double select_ms = 0.0;
  size_t batch_start = 0;
  while (batch_start < chunks.size()) {
    size_t batch_end = batch_start;
    uint32_t used = 0;
    while (batch_end < chunks.size() && (batch_end == batch_start || used + chunks[batch_end].visited <= kBatchRecords))
      used += chunks[batch_end++].visited;
    const auto ts = Clock::now();
    items.clear();
    for (size_t i = batch_start; i < batch_end; ++i) add_point_items(items, uint32_t(i), chunks[i].visited);
    select_in_order(items, records, [&](const PointItem& item, std::vector<Record>& out) {
      select_records(Kernels{s.u, &chunks[item.chunk], &image}, item.begin, item.end, out);
    });
    for (const Record& rec : records) ++counts[uint32_t(rec.center_kind.w)];
    if (ctx.capture)
      for (const Record& rec : records) ctx.capture->push_back(captured(rec, f.ortho, f.px_per_unit));
    // Setup in parallel, kept in record order.
    prims.resize(records.size());
    std::vector<uint8_t> alive(records.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, records.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      Kernels k = kernels;
      for (size_t i = r.begin(); i < r.end(); ++i) alive[i] = setup(k, records[i], f, prims[i]) ? 1 : 0;
    });
    size_t kept = 0;
    for (size_t i = 0; i < prims.size(); ++i)
      if (alive[i]) prims[kept++] = prims[i];
    prims.resize(kept);
    select_ms += std::chrono::duration<double, std::milli>(Clock::now() - ts).count();
    draw_primitives(kernels, prims, f, ink, keys);
    batch_start = batch_end;
  }
  const auto t2 = Clock::now();

  // 3. Resolve (ink_resolve.comp): ink over paper, the surface's depth; the
  // result in place of the ink (accum becomes the colour, depth the depth).
  // The surface: the winning disc's linear depth, recomputed from its point.
  auto surface = [&keys, &chunks, hint = size_t(0)](size_t q) mutable {
    if (keys[q] == kEmpty) return kInf;
    const uint32_t key = uint32_t(keys[q]);
    if (key - chunks[hint].key_base >= chunks[hint].count) {
      auto it = std::upper_bound(chunks.begin(), chunks.end(), key,
                                 [](uint32_t k, const Chunk& c) { return k < c.key_base; });
      hint = size_t(it - chunks.begin()) - 1;
    }
    const Chunk& c = chunks[hint];
    return -transform(c.view, c.positions[c.first + (key - c.key_base)]).z;
  };
  const std::vector<glm::ivec2> row_span = resolve_ink(ink, size, s.paper, surface);
  const auto t3 = Clock::now();
  upload_cpu_mark(ctx.targets, clip, ink.accum, ink.depth, row_span, ctx.coverage, "feature strokes");
  report();
  if (ctx.stats) {
    auto ms = [](Clock::time_point a, Clock::time_point b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    (*ctx.stats)["native_discs_ms"] += ms(t0, t1);
    (*ctx.stats)["native_select_ms"] += select_ms;
    (*ctx.stats)["native_primitives_ms"] += ms(t1, t2) - select_ms;
    (*ctx.stats)["native_resolve_ms"] += ms(t2, t3);
    (*ctx.stats)["native_upload_ms"] += ms(t3, Clock::now());
  }
}

}  // namespace pointnpr
