// Stippling of point clouds without normals (seed 003, Kawata et al.: a
// hybrid image/object-space stipple method). This file decides what runs
// over which window of the frame; the passes are in marks/stipples/gl.cpp
// (shaders/stipples.comp) and marks/stipples/native.cpp (the CPU's threads), both
// behind marks/stipples/stipples.h. Positions and point ids are all they read.
//
//  1. Hidden points: all points into a min-depth texture `resolution_factor`
//     times the screen; each of `iterations` passes gives every texel the
//     depth of its 8 neighbours plus a step (`depth_offset` x the segment's
//     view depth range: the paper's 0.05 on a shape of norm 1, made scale
//     free); a point is visible when it lies within a step of its texel.
//  2. Diffuse: points into a light-view min-depth texture (orthographic
//     along the light, over the segment's bounds), reduced to the full
//     quadtree (levels 0..n side by side in one 2^(n+1) x 2^n texture, each
//     texel the min of its four children); at LEVEL l the point closest to
//     the light in each cell is hidden, so lit surfaces (few points per
//     cell seen from the light) thin out and surfaces turned away keep
//     their density. A fractional LEVEL picks the finer level per point
//     with that probability (seeded by the point id), so it keyframes
//     smoothly. The casters are all points (shadows) or the visible ones.
//  3. Specular: points per area seen from the eye (cells of the hidden-
//     point texture, area = the covered texels) and from the light (cells
//     of the same size in scene units): a surface shows a (n.v) and a (n.l)
//     of area per point, so their sum peaks where it faces the half-way
//     vector. Its difference to the segment's peak, normalised by the peak,
//     below tau opens the highlight: hidden with probability 1 - diff / tau.
//  4. Dots: antialiased discs of the dot colour over the paper colour
//     (painted where the hidden-point texture has a surface), coverage by
//     atomicMax and depth by atomicMin: order-independent, so the bytes
//     never vary.
#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "core/sparse_growth.h"
#include "marks/stipples/stipples.h"
#include "render/backend.h"
#include "render/box_projection.h"
#include "scene/camera.h"

namespace pointnpr {
namespace {

constexpr double kMaxFineTexels = double(1 << 23);  // hidden-point texture cap (32 MiB per copy, 5 copies)
constexpr int kMaxLevel = 11;                        // quadtree texture 4096 x 2048 (32 MiB)
constexpr int kMaxLightCells = 1024;                 // per side (4 MiB)
constexpr double kSpecularPercentile = 0.95;  // the reference of the specular measure
// The eye cells the tone counts points in without the specular (whose
// `specular_cell` they are with it): a few dots' spacing, so the density
// follows the surface's and not single dots'.
constexpr double kToneCell = 8.0;

// The eye cells' size in pixels.
double eye_cell_px(const ParamValues& p) {
  return p.get_bool("specular") ? p.get_float("specular_cell") : kToneCell;
}
bool counts_eye(const ParamValues& p) { return p.get_bool("specular") || p.get_float("tone") > 0.0; }
bool level_from_spacing(const ParamValues& p) {
  return p.get_bool("diffuse") && p.get_enum_name("level_scale") == "spacing";
}
bool lit_share(const ParamValues& p) { return level_from_spacing(p) && p.get_enum_name("lit_rule") == "share"; }
bool spreads(const ParamValues& p) { return p.get_bool("spread_from_spacing"); }
// Fine texels a point's depth reaches: the most its own spread covers, and the iterations.
int reach_texels(const ParamValues& p) { return p.get_int("iterations") + (spreads(p) ? kStippleMaxSpread : 0); }
// Area per point over the squared spacing (the mean distance to 8
// neighbours): a square grid's, spacing (4 + 4 sqrt 2) / 8 of its step.
constexpr double kAreaPerSpacing = 0.686;

class Stipples final : public Mark {
 public:
  AttributeSet attributes(const ParamValues& p) const override {
    AttributeSet set{{AttributeKind::PointId}};
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    if (p.get_bool("opacity_draws")) set.insert({AttributeKind::SplatOpacity});
    if (level_from_spacing(p) || spreads(p)) set.insert({AttributeKind::LocalResolution, kStippleSpacingNeighbors});
    if (lit_share(p)) set.insert({AttributeKind::Normal, kStippleNormalNeighbors});
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override {
    // With a tone, a dot grows and moves by up to 1.5 dot sizes (tone_dot).
    const bool tone = p.get_float("tone") > 0.0;
    const double growth = tone ? kMaxSparseGrowth : 1.0, moved = tone ? 1.5 * p.get_float("dot_size") : 0.0;
    const double dot = 0.5 * p.get_float("dot_size") * (1.0 + p.get_float("size_jitter")) * growth + moved + 1.0;
    const double spread = double(reach_texels(p) + 1) / p.get_float("resolution_factor") + 1.0;
    return {0.0, float(std::max(dot, spread))};
  }

  void draw(const MarkContext& ctx, const ParamValues& p) const override;

  // Per-point decisions use frame pixels and texels anchored at the frame's
  // corner; what depends on every visible point is computed once per frame.
  bool draws_tiles(const ParamValues& /*p*/) const override { return true; }
  // Beyond the dot (the extent): a dot's visibility reads the reach
  // (`iterations` and a point's own spread) around it, the paper the visible
  // points spread reach + 1 texels further, and the specular's and the
  // tone's sums 2.5 cells (and their closed coverage 2 x reach texels)
  // around the dot.
  // (At the lowest factor draw() may lower it to: one texel per pixel.)
  int screen_reach(const ParamValues& p) const override {
    const double f = std::min(p.get_float("resolution_factor"), 1.0);
    const double k = double(reach_texels(p));
    double reach = (2.0 * k + 1.0) / f;
    if (counts_eye(p)) reach = std::max(reach, 2.5 * eye_cell_px(p) + 3.0 * k / f);
    return int(std::ceil(reach)) + 3;
  }

 private:
  // auto (render/backend.h): the native passes on a software GL, GL on a GPU.
  static bool native(const ParamValues& p) { return chosen_backend(p) == Backend::Native; }
};

// Texels floor(x * factor) of the frame pixels [r.min, r.max), within the
// frame's fine texels [lo, hi) (a window ends where the segment's does).
StippleWindow make_window(const Rect& r, float factor, float eye_cell, glm::ivec2 lo, glm::ivec2 hi) {
  StippleWindow w;
  w.px = r;
  w.k.fine_min = glm::max(glm::ivec2(glm::floor(glm::vec2(r.min) * factor)), lo);
  w.k.fine_size = glm::max(glm::min(glm::ivec2(glm::ceil(glm::vec2(r.max) * factor)), hi) - w.k.fine_min, glm::ivec2(1));
  w.k.eye_min = glm::ivec2(glm::floor(glm::vec2(r.min) / eye_cell));
  w.k.eye_cells = glm::max(glm::ivec2(glm::ceil(glm::vec2(r.max) / eye_cell)) - w.k.eye_min, glm::ivec2(1));
  return w;
}

// Windows over the frame rectangle `all`: interiors of at most `interior`
// pixels per side, each grown by `halo` (within `all`), owning the fine
// texels of its interior.
std::vector<StippleWindow> sweep_windows(const Rect& all, glm::ivec2 interior, int halo, float factor,
                                         float eye_cell, glm::ivec2 lo, glm::ivec2 hi) {
  std::vector<StippleWindow> out;
  for (int y = all.min.y; y < all.max.y; y += interior.y)
    for (int x = all.min.x; x < all.max.x; x += interior.x) {
      const Rect in{{x, y}, glm::min(glm::ivec2(x, y) + interior, all.max)};
      const Rect grown{glm::max(in.min - halo, all.min), glm::min(in.max + halo, all.max)};
      StippleWindow w = make_window(grown, factor, eye_cell, lo, hi);
      for (int k = 0; k < 2; ++k) {
        if (in.min[k] > all.min[k]) w.k.owned_min[k] = int(std::floor(float(in.min[k]) * factor));
        if (in.max[k] < all.max[k]) w.k.owned_max[k] = int(std::floor(float(in.max[k]) * factor));
      }
      out.push_back(w);
    }
  return out;
}

// The reference: one bin (2^(1/8)) above the percentile, which is
// interpolated within its bin (log2 scale) by the share of the bin's
// points below it. Earlier it was the upper edge of the percentile's
// bin, which jumped by a bin as the counts moved (and the highlight's
// rim with it); this keeps that margin and moves smoothly.
float specular_reference(const std::vector<uint32_t>& hist) {
  uint64_t total = 0;
  for (uint32_t h : hist) total += h;
  const double want = kSpecularPercentile * double(total);
  uint64_t sum = 0;
  double position = kStippleHistogramBins;
  for (int b = 0; b < kStippleHistogramBins; ++b) {
    const uint32_t h = hist[size_t(b)];
    if (h > 0 && double(sum + h) >= want) {
      position = double(b) + std::clamp((want - double(sum)) / double(h), 0.0, 1.0);
      break;
    }
    sum += h;
  }
  return float(std::exp2((position + 1.0) / 8.0 - 64.0));
}

void Stipples::draw(const MarkContext& ctx, const ParamValues& p) const {
  const Camera& cam = *ctx.camera;
  const Rect& clip = ctx.clip;
  if (clip.empty() || ctx.chunks.empty()) return;
  // Everything decided per frame comes from the whole frame's segment (its
  // chunks, its rectangle), so a tile decides every point as the frame does.
  const glm::ivec2 origin_px = ctx.targets.origin;
  const glm::ivec2 frame_px = frame_size(ctx.targets);
  const bool tiled = origin_px != glm::ivec2(0) || ctx.targets.size != frame_px;
  const std::span<const VisibleChunk> frame_chunks = ctx.frame_chunks.empty() ? ctx.chunks : ctx.frame_chunks;
  const Rect frame_clip = ctx.frame_clip.empty() ? Rect{clip.min + origin_px, clip.max + origin_px} : ctx.frame_clip;
  const glm::ivec2 frame_clip_size = frame_clip.size();
  const double pixels = double(frame_clip_size.x) * double(frame_clip_size.y);
  double factor = p.get_float("resolution_factor");
  if (pixels * factor * factor > kMaxFineTexels) {
    // By the segment's size in the frame, so every tile lowers it alike;
    // never below one texel per pixel (tiles bound the memory then).
    factor = std::max(std::sqrt(kMaxFineTexels / pixels), std::min(factor, 1.0));
    if (ctx.warnings && !(tiled && ctx.frame_cache && *ctx.frame_cache))  // once per frame
      ctx.warnings->push_back("stipples: resolution_factor lowered to " + std::to_string(factor) +
                              " (hidden-point texture capped at 8M texels)");
  }
  StippleSetup s;
  s.params = &p;
  stipples::StippleSettings& u = s.u;
  u.projection = glm::mat4(cam.projection);
  u.frame_px = frame_px;
  u.origin_px = origin_px;
  s.clip = clip;
  u.clip_min = clip.min;
  u.clip_max = clip.max;
  u.near_plane = float(cam.clip_start);
  u.far_plane = float(cam.clip_end);
  u.ortho = cam.orthographic ? 1 : 0;
  const float f = u.factor = float(factor);
  s.iterations = p.get_int("iterations");
  if (spreads(p)) {
    u.spread_max = kStippleMaxSpread;
    s.spread_scale = 0.5 * double(factor) * cam.pixels_per_unit(1.0, frame_px.y);
  }
  s.opacity_draws = p.get_bool("opacity_draws");
  u.px_per_unit = float(cam.pixels_per_unit(1.0, frame_px.y));
  const float range = float(std::max(ctx.depth_max - ctx.depth_min, 1e-6));
  u.offset = float(p.get_float("depth_offset")) * range;

  // Light frame: its axes and bounds are fixed in the world (a world light's
  // cells then stay on the same points as the camera moves: the quadtree
  // decides the same dots in every frame), handed to the shader in view
  // space: (right, up) . view - origin = (right, up) . world - world origin.
  const glm::dmat3 view_from_world(cam.view_from_world);
  const glm::dvec3 view_translation(cam.view_from_world[3]);
  const glm::vec3 L = view_light_direction(p, cam);
  const glm::dvec3 L_world = glm::normalize(glm::transpose(view_from_world) * glm::dvec3(L));
  const glm::dvec3 up0 = std::abs(L_world.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 right_world = glm::normalize(glm::cross(up0, L_world));
  const glm::dvec3 up_world = glm::cross(L_world, right_world);
  const glm::vec3 right(view_from_world * right_world), up(view_from_world * up_world);
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const VisibleChunk& v : frame_chunks)
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? v.chunk->local_max.x : v.chunk->local_min.x,
                             (c & 2) ? v.chunk->local_max.y : v.chunk->local_min.y,
                             (c & 4) ? v.chunk->local_max.z : v.chunk->local_min.z);
      const glm::dvec3 world = glm::transpose(view_from_world) *
                               (glm::dvec3(glm::vec3(v.view_from_chunk * glm::vec4(corner, 1.0f))) - view_translation);
      const glm::dvec2 uv(glm::dot(world, right_world), glm::dot(world, up_world));
      lo = glm::min(lo, uv), hi = glm::max(hi, uv);
    }
  const double extent_d = std::max(std::max(hi.x - lo.x, hi.y - lo.y), 1e-6) * 1.001;
  const glm::dvec2 origin_world = 0.5 * (lo + hi) - 0.5 * extent_d;
  u.light_dir = glm::vec4(L, 0.0f);
  u.light_right = glm::vec4(right, 0.0f);
  u.light_up = glm::vec4(up, 0.0f);
  u.light_extent = float(extent_d);
  u.light_origin = glm::vec2(origin_world + glm::dvec2(glm::dot(view_translation, glm::dvec3(right)),
                                                       glm::dot(view_translation, glm::dvec3(up))));

  const bool diffuse = p.get_bool("diffuse"), casters_all = p.get_enum_name("shadow_casters") == "all";
  // The light-view quadtree: the nearest rule's, and the share rule's cast shadows.
  const bool quadtree = diffuse && !(lit_share(p) && p.get_enum_name("shadow_casters") == "none");
  u.quadtree = quadtree ? 1 : 0;
  u.diffuse = diffuse ? 1 : 0;
  u.casters_all = casters_all ? 1 : 0;
  double level = p.get_float("level");
  if (diffuse && p.get_enum_name("level_scale") == "point_count") {
    // LEVEL as for 4^7 points: a cloud of N points gets log4(N / 4^7)
    // levels more, so 2^level cells hold as many points whatever the scan.
    double points = 0.0;
    for (const VisibleChunk& v : frame_chunks) points += double(v.chunk->count);
    level = std::clamp(level + 0.5 * std::log2(std::max(points, 1.0) / 16384.0), 0.0, double(kMaxLevel));
  }
  u.levels = std::clamp(int(std::ceil(level)), 1, kMaxLevel);
  if (level_from_spacing(p)) {
    // Each point's cells as wide as its spacing at LEVEL 8 (halved per
    // level above): the quadtree reaches two levels below the cells of
    // the segment's finest median spacing, for its denser points.
    u.level_from_spacing = 1;
    s.spacing_cell_scale = std::exp2(8.0 - level);
    double finest = std::numeric_limits<double>::max();
    for (const VisibleChunk& v : frame_chunks)
      finest = std::min(finest, spacing_cell_scale(s, v) * double(median_spacing(v, kStippleSpacingNeighbors, 0.0f)));
    const double levels = finest > 0.0 && finest < extent_d ? std::ceil(std::log2(extent_d / finest)) + 2.0 : 1.0;
    u.levels = int(std::clamp(levels, 1.0, double(kMaxLevel)));
  }
  u.level_lo = std::min(int(std::floor(level)), u.levels);
  u.level_frac = float(level - std::floor(level));
  u.lit_share = lit_share(p) ? 1 : 0;
  // The share of lit points the nearest rule hides on average: a point's
  // area on the light's plane (its surface area, a (n.l)) over its cell's
  // (w^2). Its area is kAreaPerSpacing times its spacing squared, and its
  // cell is its spacing times 2^(8 - LEVEL) wide.
  u.share_scale = float(kAreaPerSpacing * std::exp2(2.0 * (level - 8.0)));
  const bool specular = p.get_bool("specular");
  // The highlight takes its share from the diffuse light (k_d + k_s = 1):
  // opened where the diffuse share alone already leaves paper, it shows
  // nowhere.
  if (specular) u.share_scale *= float(1.0 - p.get_float("specular_share"));
  u.specular = specular ? 1 : 0;
  u.tau = float(p.get_float("tau"));
  const float eye_cell = u.eye_cell = float(eye_cell_px(p));
  // Dots of dot_size per pixel of surface for the tone's ink: dots at
  // random cover 1 - exp(-density x area) of it.
  const double tone = p.get_float("tone");
  const double dot_size = p.get_float("dot_size");
  u.tone_scale = tone > 0.0 ? float(-std::log1p(-tone) / (0.25 * M_PI * dot_size * dot_size)) : 0.0f;
  const double mid_depth = cam.orthographic ? 1.0 : 0.5 * (ctx.depth_min + ctx.depth_max);
  const double cell_world = eye_cell * mid_depth / u.px_per_unit;
  u.light_cells = std::clamp(int(std::ceil(u.light_extent / cell_world)), 1, kMaxLightCells);
  u.dot_size = float(p.get_float("dot_size"));
  u.size_jitter = float(p.get_float("size_jitter"));
  u.seed = uint32_t(p.get_int("seed"));
  u.dot_color = p.get_color("dot_color");
  u.paper = p.get_color("paper_color");
  u.capture = ctx.capture != nullptr ? 1 : 0;

  // Fine texels and eye cells are anchored at the frame's corner (frame
  // pixel x lies in texel floor(x * factor)), so they stay put when the
  // segment's rectangle moves and are the same in every tile.
  const glm::ivec2 fine_lo(glm::floor(glm::vec2(frame_clip.min) * f));
  const glm::ivec2 fine_hi(glm::ceil(glm::vec2(frame_clip.max) * f));
  const Rect draw_px{glm::max(clip.min + origin_px, frame_clip.min), glm::min(clip.max + origin_px, frame_clip.max)};
  const StippleWindow draw_window = make_window(draw_px, f, eye_cell, fine_lo, fine_hi);

  const std::unique_ptr<StipplePasses> passes =
      native(p) ? make_native_stipple_passes(ctx, s) : make_gl_stipple_passes(ctx, s);
  float spec_ref = 1.0f;
  if (!tiled) {
    // The frame whole: one window does the frame's counts and the drawing.
    passes->hidden_points(draw_window, ctx.chunks, true, quadtree && casters_all, true);
    if (quadtree) passes->reduce_quadtree();
    if (s.counts_eye()) passes->cover();
    if (specular) {
      passes->specular_histogram(ctx.chunks);
      spec_ref = specular_reference(passes->histogram());
    }
  } else {
    // A tile: the frame's quadtree, light counts and reference once (the
    // first tile), over windows of the tile's size that each own their
    // interior's points and read a halo around it; then the tile's window.
    auto* cached = ctx.frame_cache ? dynamic_cast<StippleFrameState*>(ctx.frame_cache->get()) : nullptr;
    std::unique_ptr<StippleFrameState> uncached;  // without a frame cache, each tile computes it again
    if (!cached) {
      auto state = std::make_unique<StippleFrameState>();
      if (quadtree && casters_all) passes->project_casters(frame_chunks);
      // Visibility reads the reach's texels; an eye cell's sums read 2.5
      // cells and its closed coverage 2 x the reach beyond.
      const int visibility_halo = int(std::ceil(float(s.reach_texels()) / f)) + 2;
      const int specular_halo = int(std::ceil(2.5f * eye_cell + 2.0f * float(s.reach_texels()) / f)) + visibility_halo;
      auto sweep = [&](int halo) {
        const glm::ivec2 interior = glm::max(ctx.targets.size - 2 * halo, glm::ivec2(64));
        return sweep_windows(frame_clip, interior, halo, f, eye_cell, fine_lo, fine_hi);
      };
      // Each window projects only the chunks whose box reaches it (a
      // conservative rectangle: a point outside its window is dropped anyway).
      std::vector<Rect> chunk_rects;
      for (const VisibleChunk& v : frame_chunks)
        chunk_rects.push_back(project_box(glm::dmat4(v.view_from_chunk), glm::dvec3(v.chunk->local_min),
                                          glm::dvec3(v.chunk->local_max), cam, frame_px)
                                  .rect(frame_px, 2.0));
      std::vector<VisibleChunk> reaching;
      auto chunks_in = [&](const StippleWindow& w) {
        reaching.clear();
        for (size_t i = 0; i < frame_chunks.size(); ++i) {
          const Rect& r = chunk_rects[i];
          if (r.min.x < w.px.max.x && r.max.x > w.px.min.x && r.min.y < w.px.max.y && r.max.y > w.px.min.y)
            reaching.push_back(frame_chunks[i]);
        }
        return std::span<const VisibleChunk>(reaching);
      };
      if ((quadtree && !casters_all) || specular)
        for (const StippleWindow& w : sweep(visibility_halo)) passes->hidden_points(w, chunks_in(w), true, false, false);
      if (quadtree) passes->reduce_quadtree();
      if (specular) {
        for (const StippleWindow& w : sweep(specular_halo)) {
          const std::span<const VisibleChunk> chunks = chunks_in(w);
          passes->hidden_points(w, chunks, false, false, false);
          passes->cover();
          passes->specular_histogram(chunks);
        }
        state->spec_ref = specular_reference(passes->histogram());
      }
      passes->save(*state);
      cached = state.get();
      if (ctx.frame_cache)
        *ctx.frame_cache = std::move(state);
      else
        uncached = std::move(state);
    } else {
      passes->load(*cached);
    }
    spec_ref = cached->spec_ref;
    passes->hidden_points(draw_window, ctx.chunks, false, false, true);
    if (s.counts_eye()) passes->cover();
  }
  const uint32_t visible = passes->visible();
  // 4. Dots.
  const uint32_t kept = passes->draw_dots(ctx.chunks, spec_ref, ctx.capture);
  passes->resolve();
  gl::check_gl("stipples");
  if (ctx.stats) {
    // In tiles, the points of each tile's halo are counted again.
    (*ctx.stats)["stipples_visible"] += double(visible);
    (*ctx.stats)["stipples_drawn"] += double(kept);
  }
}

}  // namespace

// With the view's scale of object lengths (the instance's; the view keeps them).
float spacing_cell_scale(const StippleSetup& s, const VisibleChunk& v) {
  return float(s.spacing_cell_scale * std::cbrt(std::abs(glm::determinant(glm::dmat3(v.view_from_chunk)))));
}
float spread_scale(const StippleSetup& s, const VisibleChunk& v) { return float(s.spread_scale * view_scale(v)); }
float spread_cap(const VisibleChunk& v) {
  return sparse_spacing(v, kStippleSpacingNeighbors, std::numeric_limits<float>::max());
}

CapturedMark captured_dot(const StippleSetup& s, glm::vec3 center, uint32_t id) {
  CapturedMark m;
  m.point_id = id;
  m.center = center;
  m.direction = glm::vec3(1, 0, 0);
  const float len = glm::length(m.center);
  m.normal = len > 0.0f ? -m.center / len : glm::vec3(0, 0, 1);
  m.length = s.u.dot_size;
  m.color = s.u.dot_color;
  return m;
}

namespace {

const MarkRegistration registration{{
    Schema{"stipples",
           "Stipples",
           "Stippling without normals (seed 003): hidden points removed in image space, shading by the density "
           "of dots (a light-view min-depth quadtree thins lit surfaces; point counts seen from eye and light "
           "open highlights).",
           {
               formerly(rasterizer_param("gl: the passes as GL compute shaders (for GPUs); native: the same "
                                         "rules on the CPU's threads (the same dots)"),
                        {"implementation"}),
               float_param("dot_size", 2.0, 0.5, 16.0, "px", "Dot diameter"),
               float_param("size_jitter", 0.0, 0.0, 1.0, "", "Random size variation per dot (seeded by the point id)"),
               color_param("dot_color", {0.0, 0.0, 0.0, 1.0}, "Dot colour (display sRGB; alpha: its opacity)"),
               paper_color_param({1.0, 1.0, 1.0, 1.0}, "dots"),
               added_later(float_param("tone", 0.7, 0.0, 0.95, "",
                                       "Ink of a surface turned from the light: where the visible points crowd on "
                                       "screen a share of them draws, where they are sparse their dots grow (to 3x), "
                                       "so the dots cover about this share of it at any scan density and output "
                                       "size; the light then thins it. 0: every visible point draws one dot (the "
                                       "paper's: ink follows the density)"),
                           {0.0}),
               int_param("iterations", 3, 0, 32, "",
                         "Hidden points: how many times each texel takes its neighbours' depths (closes holes "
                         "between front points of this many texels)"),
               added_later(bool_param("spread_from_spacing", true,
                                      "Hidden points: each point first covers half its own spacing on screen (at "
                                      "most 8 texels each way), so a sparse surface closes, hides what lies behind "
                                      "it and counts its whole area for the tone; the iterations then add their "
                                      "texels (off: the iterations alone, the paper's)"),
                           {0.0}),
               float_param("depth_offset", 0.038, 0.0, 0.5, "",
                           "Hidden points: depth added per spreading step and kept in front of the surface, as a "
                           "fraction of the segment's view depth range (the paper's 'slightly larger depth')"),
               float_param("resolution_factor", 1.25, 1.0, 4.0, "",
                           "Hidden-point texture size over the screen's (larger: fewer front points lost where "
                           "they crowd, more iterations needed)"),
               // A key light with the camera by default (a world light's Z axis lit Y-down depth frames
               // from behind); files saved before keep the world light.
               default_changed(light_space_param(1), {0.0}),
               light_azimuth_param(135.0),
               light_elevation_param(50.0),
               bool_param("diffuse", true, "Thin lit surfaces by the light-view quadtree"),
               only_when(default_changed(float_param("level", 9.0, 0.0, 11.0, "",
                                                     "Quadtree LEVEL: 2^LEVEL cells across the segment seen from the "
                                                     "light (per point from its spacing with level_scale spacing); about "
                                                     "one point the light reaches in each is hidden (lit_rule; higher: "
                                                     "more cells, lit areas thinner; fractions blend adjacent levels)"),
                                         {7.0}),
                         "diffuse", {"true"}),
               only_when(default_changed(enum_param("level_scale", {"absolute", "point_count", "spacing"}, 2,
                                    "absolute: LEVEL as given (the paper's); point_count: LEVEL for 16384 points, "
                                    "plus log4 of the segment's point count over that, so sparse and dense scans "
                                    "thin alike; spacing: each point's own, its cells as wide as its spacing at "
                                    "LEVEL 8 (half as wide per level above), so the lit share follows the light "
                                    "where the scan is denser or sparser"),
                                         {0.0}),
                         "diffuse", {"true"}),
               only_when(added_later(enum_param("lit_rule", {"share", "nearest"}, 0,
                                                "Which lit points stay paper: share: each point the light reaches "
                                                "(no nearer caster in its cell) by the chance the nearest rule "
                                                "gives on average, from its normal's N.L, against a number fixed "
                                                "per point (the same dots as a camera light turns); nearest: the "
                                                "point closest to the light in each cell (the paper's, no normals; "
                                                "its dots change as a turning light's cells slide)"),
                                     {1.0}),
                         "level_scale", {"spacing"}),
               // No cast shadows by default: a light turning with the camera slides its cells
               // over the points, and shadows cut by them flicker (files saved before keep all).
               only_when(default_changed(enum_param("shadow_casters", {"all", "visible", "none"}, 2,
                                                    "Points the light sees: all (hidden ones too, so surfaces behind "
                                                    "others from the light stay dense: shadows), only the visible "
                                                    "ones (as the paper's text), or none: no cast shadows, each point "
                                                    "lit by its own N.L (lit_rule share; the nearest rule needs "
                                                    "casters and takes the visible ones)"),
                                         {0.0}),
                         "diffuse", {"true"}),
               bool_param("specular", false, "Open highlights where the surface faces between eye and light"),
               only_when(float_param("tau", 0.2, 0.0, 1.0, "",
                                     "Highlight threshold: points whose normalised difference from the brightest "
                                     "area per point is below tau may be hidden (more below: more often)"),
                         "specular", {"true"}),
               also_when(only_when(added_later(float_param("specular_share", 0.3, 0.0, 1.0, "",
                                                           "The highlight's share of the light: lit surfaces keep "
                                                           "this much more of their dots (the share rule's), so the "
                                                           "highlight shows where the diffuse light alone would leave "
                                                           "paper"),
                                               {0.0}),
                                   "specular", {"true"}),
                         "lit_rule", {"share"}),
               only_when(float_param("specular_cell", 8.0, 2.0, 64.0, "px",
                                     "Size of the cells points are counted in, on screen (the light's cells are as "
                                     "large in scene units at the segment's middle depth)"),
                         "specular", {"true"}),
               density_mode_param(),
               queue_level_param(0.1),
               int_param("seed", 0, 0, 65535, "", "Varies every random choice (still fixed per point)"),
               bool_param("opacity_draws", false,
                          "A Gaussian-splat capture's opacity is each splat's chance of a dot (the same splats as "
                          "the points mark draws; its faint haze gets few; plain points: unchanged)"),
           }},
    [] { return std::make_unique<Stipples>(); }}};

}  // namespace
}  // namespace pointnpr
