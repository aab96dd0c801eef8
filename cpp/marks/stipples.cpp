// Stippling of point clouds without normals (seed 003, Kawata et al.: a
// hybrid image/object-space stipple method). Every pass is in
// shaders/stipples.comp; positions and point ids are all it reads.
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
#include "gl/device.h"
#include "render/box_projection.h"
#include "render/mark.h"
#include "scene/camera.h"

namespace pointnpr {
namespace {

constexpr double kMaxFineTexels = double(1 << 23);  // hidden-point texture cap (32 MiB per copy, 5 copies)
constexpr int kMaxLevel = 11;                        // quadtree texture 4096 x 2048 (32 MiB)
constexpr int kMaxLightCells = 1024;                 // per side (4 MiB)
constexpr int kHistogramBins = 1024;                 // log2 of the specular measure, 8 bins per octave
constexpr double kSpecularPercentile = 0.95;  // the reference of the specular measure

// Sets the first `count` uints of `b` (scratch buffers may be larger).
void clear_uint(const gl::Buffer& b, size_t count, uint32_t value) {
  glClearNamedBufferSubData(b.id(), GL_R32UI, 0, GLsizeiptr(count * 4), GL_RED_INTEGER, GL_UNSIGNED_INT, &value);
}

// Binds a chunk for a point pass; with the resolution queue on, the pass
// takes the first queue_count() points of the chunk's queue order. Returns
// how many points to dispatch.
uint32_t bind_queued_chunk(const gl::Program& prog, const VisibleChunk& v, const ParamValues& p) {
  bind_chunk(prog, v, ColorSource::Constant, {{6, v.gpu->find({AttributeKind::PointId})}});
  const bool queued = draws_queue(v, p);
  glUniform1i(prog.location("u_queue"), queued ? 1 : 0);
  if (!queued) return v.chunk->count;
  const gl::Buffer* order = v.gpu->find({AttributeKind::QueueOrder});
  if (!order) throw GLError("stipples: the queue order was not uploaded");
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 15, order->id());
  const uint32_t count = queue_count(v, p);
  glUniform1ui(prog.location("u_count"), count);
  return count;
}

class Stipples final : public Mark {
 public:
  AttributeSet attributes(const ParamValues& p) const override {
    AttributeSet set{{AttributeKind::PointId}};
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override {
    const double dot = 0.5 * p.get_float("dot_size") * (1.0 + p.get_float("size_jitter")) + 1.0;
    const double spread = double(p.get_int("iterations") + 1) / p.get_float("resolution_factor") + 1.0;
    return {0.0, float(std::max(dot, spread))};
  }

  void draw(const MarkContext& ctx, const ParamValues& p) const override;

  // Per-point decisions use frame pixels and texels anchored at the frame's
  // corner; what depends on every visible point is computed once per frame.
  bool draws_tiles(const ParamValues& /*p*/) const override { return true; }
  // Beyond the dot (the extent): a dot's visibility reads `iterations`
  // texels around it, the paper the visible points spread iterations + 1
  // texels further, and the specular sums 2.5 cells (and their closed
  // coverage 2 x iterations texels) around the dot.
  // (At the lowest factor draw() may lower it to: one texel per pixel.)
  int screen_reach(const ParamValues& p) const override {
    const double f = std::min(p.get_float("resolution_factor"), 1.0);
    const double k = double(p.get_int("iterations"));
    double reach = (2.0 * k + 1.0) / f;
    if (p.get_bool("specular")) reach = std::max(reach, 2.5 * p.get_float("specular_cell") + 3.0 * k / f);
    return int(std::ceil(reach)) + 3;
  }
};

// What the frame's tiles share, computed at its first tile from every
// visible point (bounded by the quadtree's and the light cells' caps, not by
// the frame's pixels).
struct StippleFrame final : MarkFrameCache {
  std::vector<uint32_t> quad;         // the reduced quadtree (diffuse)
  std::vector<uint32_t> light_count;  // visible points per light cell (specular)
  float spec_ref = 1.0f;
};

// A piece of the frame the hidden-point passes run over: its fine texture
// (frame texels [fine_min, fine_min + fine)), its eye cells, and the fine
// texels whose points it counts for the frame (each point in exactly one
// window's; the rest of the window is the halo its decisions read).
struct Window {
  Rect px;  // frame pixels
  glm::ivec2 fine_min{0, 0}, fine{0, 0};
  glm::ivec2 owned_min{std::numeric_limits<int>::min()}, owned_max{std::numeric_limits<int>::max()};
  glm::ivec2 eye_min{0, 0}, eye_cells{1, 1};
  size_t fine_n() const { return size_t(fine.x) * size_t(fine.y); }
  size_t eye_n() const { return size_t(eye_cells.x) * size_t(eye_cells.y); }
};

// Texels floor(x * factor) of the frame pixels [r.min, r.max), within the
// frame's fine texels [lo, hi) (a window ends where the segment's does).
Window make_window(const Rect& r, float factor, float eye_cell, glm::ivec2 lo, glm::ivec2 hi) {
  Window w;
  w.px = r;
  w.fine_min = glm::max(glm::ivec2(glm::floor(glm::vec2(r.min) * factor)), lo);
  w.fine = glm::max(glm::min(glm::ivec2(glm::ceil(glm::vec2(r.max) * factor)), hi) - w.fine_min, glm::ivec2(1));
  w.eye_min = glm::ivec2(glm::floor(glm::vec2(r.min) / eye_cell));
  w.eye_cells = glm::max(glm::ivec2(glm::ceil(glm::vec2(r.max) / eye_cell)) - w.eye_min, glm::ivec2(1));
  return w;
}

// Windows over the frame rectangle `all`: interiors of at most `interior`
// pixels per side, each grown by `halo` (within `all`), owning the fine
// texels of its interior.
std::vector<Window> sweep_windows(const Rect& all, glm::ivec2 interior, int halo, float factor, float eye_cell,
                                  glm::ivec2 lo, glm::ivec2 hi) {
  std::vector<Window> out;
  for (int y = all.min.y; y < all.max.y; y += interior.y)
    for (int x = all.min.x; x < all.max.x; x += interior.x) {
      const Rect in{{x, y}, glm::min(glm::ivec2(x, y) + interior, all.max)};
      const Rect grown{glm::max(in.min - halo, all.min), glm::min(in.max + halo, all.max)};
      Window w = make_window(grown, factor, eye_cell, lo, hi);
      for (int k = 0; k < 2; ++k) {
        if (in.min[k] > all.min[k]) w.owned_min[k] = int(std::floor(float(in.min[k]) * factor));
        if (in.max[k] < all.max[k]) w.owned_max[k] = int(std::floor(float(in.max[k]) * factor));
      }
      out.push_back(w);
    }
  return out;
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
  const float f = float(factor);
  const int iterations = p.get_int("iterations");
  const float px_per_unit = float(cam.pixels_per_unit(1.0, frame_px.y));
  const float range = float(std::max(ctx.depth_max - ctx.depth_min, 1e-6));
  const float offset = float(p.get_float("depth_offset")) * range;

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
  const float extent = float(extent_d);
  const glm::vec2 origin(origin_world + glm::dvec2(glm::dot(view_translation, glm::dvec3(right)),
                                                   glm::dot(view_translation, glm::dvec3(up))));

  const bool diffuse = p.get_bool("diffuse");
  const bool casters_all = p.get_enum_name("shadow_casters") == "all";
  double level = p.get_float("level");
  if (diffuse && p.get_enum_name("level_scale") == "point_count") {
    // LEVEL as for 4^7 points: a cloud of N points gets log4(N / 4^7)
    // levels more, so 2^level cells hold as many points whatever the scan.
    double points = 0.0;
    for (const VisibleChunk& v : frame_chunks) points += double(v.chunk->count);
    level = std::clamp(level + 0.5 * std::log2(std::max(points, 1.0) / 16384.0), 0.0, double(kMaxLevel));
  }
  const int levels = std::clamp(int(std::ceil(level)), 1, kMaxLevel);
  const int level_lo = std::min(int(std::floor(level)), levels);
  const float level_frac = float(level - std::floor(level));
  const bool specular = p.get_bool("specular");
  const float eye_cell = float(p.get_float("specular_cell"));
  const double mid_depth = cam.orthographic ? 1.0 : 0.5 * (ctx.depth_min + ctx.depth_max);
  const double cell_world = eye_cell * mid_depth / px_per_unit;
  const int light_cells = std::clamp(int(std::ceil(extent / cell_world)), 1, kMaxLightCells);

  // Fine texels and eye cells are anchored at the frame's corner (frame
  // pixel x lies in texel floor(x * factor)), so they stay put when the
  // segment's rectangle moves and are the same in every tile.
  const glm::ivec2 fine_lo(glm::floor(glm::vec2(frame_clip.min) * f));
  const glm::ivec2 fine_hi(glm::ceil(glm::vec2(frame_clip.max) * f));
  const Rect draw_px{glm::max(clip.min + origin_px, frame_clip.min), glm::min(clip.max + origin_px, frame_clip.max)};
  const Window draw_window = make_window(draw_px, f, eye_cell, fine_lo, fine_hi);

  const size_t quad_n = diffuse ? (size_t(2) << levels) * (size_t(1) << levels) : 1;
  const gl::Buffer quad = gl::make_buffer(quad_n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  const size_t light_n = specular ? size_t(light_cells) * size_t(light_cells) : 1;
  const gl::Buffer light_count = gl::make_buffer(light_n * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
  const size_t clip_pixels = size_t(clip.size().x) * size_t(clip.size().y);
  const gl::Buffer& dot_cov = ctx.targets.scratch_buffer(clip_pixels * 4, 2);
  const gl::Buffer& dot_depth = ctx.targets.scratch_buffer(clip_pixels * 4, 3);
  const gl::Buffer histogram = gl::make_buffer(specular ? kHistogramBins * 4 : 4, nullptr, 0);
  const gl::Buffer globals = gl::make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT);
  uint32_t largest = 1;
  for (const VisibleChunk& v : ctx.chunks) largest = std::max(largest, v.chunk->count);
  const gl::Buffer capture = gl::make_buffer(ctx.capture ? size_t(largest) * 16 : 16, nullptr, 0);
  const uint32_t inf_bits = 0x7f800000u;
  clear_uint(quad, quad_n, 0xffffffffu);
  clear_uint(light_count, light_n, 0);
  clear_uint(dot_cov, clip_pixels, 0);
  clear_uint(dot_depth, clip_pixels, inf_bits);
  clear_uint(globals, 4, 0);
  clear_uint(histogram, (specular ? kHistogramBins : 1), 0);
  float spec_ref = 1.0f;

  // The window the passes run over, and what its point passes do.
  const Window* win = &draw_window;
  bool project_hp = true, project_quad = false, accumulate = false;
  size_t eye_n = 1;
  const gl::Buffer* eye_count = nullptr;
  const gl::Buffer* eye_cover = nullptr;
  auto set_uniforms = [&](const gl::Program& prog) {
    prog.use();
    glUniformMatrix4fv(prog.location("u_projection"), 1, GL_FALSE, glm::value_ptr(glm::mat4(cam.projection)));
    glUniform2i(prog.location("u_size"), frame_px.x, frame_px.y);
    glUniform2i(prog.location("u_origin"), origin_px.x, origin_px.y);
    glUniform1f(prog.location("u_near"), float(cam.clip_start));
    glUniform1f(prog.location("u_far"), float(cam.clip_end));
    glUniform1i(prog.location("u_ortho"), cam.orthographic ? 1 : 0);
    glUniform1f(prog.location("u_px_per_unit"), px_per_unit);
    glUniform2i(prog.location("u_clip_min"), clip.min.x, clip.min.y);
    glUniform2i(prog.location("u_clip_max"), clip.max.x, clip.max.y);
    glUniform1f(prog.location("u_factor"), f);
    glUniform2i(prog.location("u_fine_min"), win->fine_min.x, win->fine_min.y);
    glUniform2i(prog.location("u_fine_size"), win->fine.x, win->fine.y);
    glUniform2i(prog.location("u_owned_min"), win->owned_min.x, win->owned_min.y);
    glUniform2i(prog.location("u_owned_max"), win->owned_max.x, win->owned_max.y);
    glUniform1i(prog.location("u_project_hp"), project_hp ? 1 : 0);
    glUniform1i(prog.location("u_project_quad"), project_quad ? 1 : 0);
    glUniform1i(prog.location("u_accumulate"), accumulate ? 1 : 0);
    glUniform1f(prog.location("u_offset"), offset);
    glUniform1i(prog.location("u_casters_all"), casters_all ? 1 : 0);
    glUniform3fv(prog.location("u_light_dir"), 1, glm::value_ptr(L));
    glUniform3fv(prog.location("u_light_right"), 1, glm::value_ptr(right));
    glUniform3fv(prog.location("u_light_up"), 1, glm::value_ptr(up));
    glUniform2fv(prog.location("u_light_origin"), 1, glm::value_ptr(origin));
    glUniform1f(prog.location("u_light_extent"), extent);
    glUniform1i(prog.location("u_levels"), levels);
    glUniform1i(prog.location("u_diffuse"), diffuse ? 1 : 0);
    glUniform1i(prog.location("u_level_lo"), level_lo);
    glUniform1f(prog.location("u_level_frac"), level_frac);
    glUniform1i(prog.location("u_specular"), specular ? 1 : 0);
    glUniform1f(prog.location("u_tau"), float(p.get_float("tau")));
    glUniform1f(prog.location("u_spec_ref"), spec_ref);
    glUniform1f(prog.location("u_eye_cell"), eye_cell);
    glUniform2i(prog.location("u_eye_min"), win->eye_min.x, win->eye_min.y);
    glUniform2i(prog.location("u_eye_cells"), win->eye_cells.x, win->eye_cells.y);
    glUniform1i(prog.location("u_light_cells"), light_cells);
    glUniform1f(prog.location("u_dot_size"), float(p.get_float("dot_size")));
    glUniform1f(prog.location("u_size_jitter"), float(p.get_float("size_jitter")));
    glUniform1ui(prog.location("u_seed"), uint32_t(p.get_int("seed")));
    glUniform1i(prog.location("u_capture"), ctx.capture ? 1 : 0);
    glUniform4fv(prog.location("u_dot_color"), 1, glm::value_ptr(p.get_color("dot_color")));
    glUniform4fv(prog.location("u_paper"), 1, glm::value_ptr(p.get_color("paper_color")));
  };
  const gl::Buffer* hp = nullptr;
  const gl::Buffer* hp_other = nullptr;
  auto bind_all = [&]() {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, hp->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, hp_other->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, quad.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, eye_count->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, eye_cover->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, light_count.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, dot_cov.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, dot_depth.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, globals.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, capture.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 14, histogram.id());
  };
  auto barrier = [] { glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); };
  auto point_pass = [&](const char* pass, std::span<const VisibleChunk> chunks) {
    const gl::Program& prog = ctx.shaders->compute("stipples.comp", {pass});
    set_uniforms(prog);
    bind_all();
    // Chunks of one pass touch the buffers only through atomics or reads of
    // earlier passes: one barrier after the pass.
    for (const VisibleChunk& v : chunks) {
      const uint32_t count = bind_queued_chunk(prog, v, p);
      if (count > 0) glDispatchCompute((count + 127) / 128, 1, 1);
    }
    barrier();
  };
  auto image_pass = [&](const char* pass, glm::ivec2 size) {
    const gl::Program& prog = ctx.shaders->compute("stipples.comp", {pass});
    set_uniforms(prog);
    bind_all();
    glDispatchCompute(GLuint((size.x + 15) / 16), GLuint((size.y + 15) / 16), 1);
    barrier();
  };

  // One window's hidden points (1.) and visible points: hp ends as the
  // spread depth; PASS_VISIBLE counts the visible points per eye cell and,
  // with `accumulate`, the frame's (quadtree casters, light cells) for the
  // points the window owns. `surface` (the draw window): the visible points
  // spread for the paper.
  auto run_window = [&](const Window& w, std::span<const VisibleChunk> chunks, bool for_frame,
                        const gl::Buffer** surface) {
    win = &w;
    const size_t n = w.fine_n();
    const gl::Buffer& hp_a = ctx.targets.scratch_buffer(n * 4, 0);
    const gl::Buffer& hp_b = ctx.targets.scratch_buffer(n * 4, 1);
    eye_n = specular ? w.eye_n() : 1;
    eye_count = &ctx.targets.scratch_buffer(eye_n * 4, 7);
    eye_cover = &ctx.targets.scratch_buffer(eye_n * 4, 8);
    clear_uint(hp_a, n, inf_bits);
    clear_uint(hp_b, n, inf_bits);
    clear_uint(*eye_count, eye_n, 0);
    clear_uint(*eye_cover, eye_n, 0);
    hp = &hp_a;
    hp_other = &hp_b;
    project_hp = true;
    point_pass("PASS_PROJECT", chunks);
    project_quad = false;
    for (int it = 0; it < iterations; ++it) {
      image_pass("PASS_DILATE", w.fine);
      std::swap(hp, hp_other);
    }
    const gl::Buffer& surf_a = ctx.targets.scratch_buffer(n * 4, 4);
    const gl::Buffer& surf_b = ctx.targets.scratch_buffer(n * 4, 5);
    clear_uint(surf_a, n, inf_bits);
    const gl::Buffer* spare = hp_other;
    hp_other = &surf_a;
    accumulate = for_frame;
    point_pass("PASS_VISIBLE", chunks);
    accumulate = false;
    hp_other = spare;
    if (surface) {
      // The surface's depth for the paper: the visible points spread one
      // texel further (they are fewer than all points), without the step
      // (the nearest visible depth).
      const gl::Buffer* keep_hp = hp;
      hp = &surf_a;
      hp_other = &surf_b;
      const gl::Program& dilate = ctx.shaders->compute("stipples.comp", {"PASS_DILATE"});
      for (int it = 0; it < iterations + 1; ++it) {
        set_uniforms(dilate);
        glUniform1f(dilate.location("u_offset"), 0.0f);
        bind_all();
        glDispatchCompute(GLuint((w.fine.x + 15) / 16), GLuint((w.fine.y + 15) / 16), 1);
        barrier();
        std::swap(hp, hp_other);
      }
      *surface = hp;
      hp = keep_hp;
      hp_other = spare;
    }
  };
  // The covered area per eye cell: the hidden-point texture closed (its
  // spreading undone at the silhouette by as many erosions). Leaves hp as
  // the spread depth.
  auto cover_window = [&](const Window& w) {
    const gl::Buffer& mask = ctx.targets.scratch_buffer(w.fine_n() * 4, 6);
    const gl::Buffer* dilated = hp;
    const gl::Buffer* spare = hp_other;
    const gl::Buffer* masks[2] = {&mask, hp_other};  // hp_other: free once the spreading is done
    for (int it = 0; it < iterations; ++it) {
      hp_other = masks[it % 2];
      image_pass("PASS_ERODE", w.fine);
      hp = hp_other;
    }
    image_pass("PASS_COVER", w.fine);
    hp = dilated;
    hp_other = spare;
  };
  auto reduce_quad = [&] {
    const gl::Program& reduce = ctx.shaders->compute("stipples.comp", {"PASS_REDUCE"});
    for (int l = levels - 1; l >= 0; --l) {
      set_uniforms(reduce);
      bind_all();
      glUniform1i(reduce.location("u_reduce_level"), l);
      const GLuint groups = GLuint(((1 << l) + 15) / 16);
      glDispatchCompute(groups, groups, 1);
      barrier();
    }
  };
  auto reference = [&] {
    // The reference: one bin (2^(1/8)) above the percentile, which is
    // interpolated within its bin (log2 scale) by the share of the bin's
    // points below it. Earlier it was the upper edge of the percentile's
    // bin, which jumped by a bin as the counts moved (and the highlight's
    // rim with it); this keeps that margin and moves smoothly.
    std::vector<uint32_t> hist(kHistogramBins);
    glGetNamedBufferSubData(histogram.id(), 0, GLsizeiptr(kHistogramBins * 4), hist.data());
    uint64_t total = 0;
    for (uint32_t h : hist) total += h;
    const double want = kSpecularPercentile * double(total);
    uint64_t sum = 0;
    double position = kHistogramBins;
    for (int b = 0; b < kHistogramBins; ++b) {
      const uint32_t h = hist[size_t(b)];
      if (h > 0 && double(sum + h) >= want) {
        position = double(b) + std::clamp((want - double(sum)) / double(h), 0.0, 1.0);
        break;
      }
      sum += h;
    }
    return float(std::exp2((position + 1.0) / 8.0 - 64.0));
  };

  const gl::Buffer* surface_depth = nullptr;
  if (!tiled) {
    // The frame whole: one window does the frame's counts and the drawing.
    project_quad = diffuse && casters_all;
    run_window(draw_window, ctx.chunks, true, &surface_depth);
    if (diffuse) reduce_quad();
    if (specular) {
      cover_window(draw_window);
      point_pass("PASS_SPECULAR", ctx.chunks);
      spec_ref = reference();
    }
  } else {
    // A tile: the frame's quadtree, light counts and reference once (the
    // first tile), over windows of the tile's size that each own their
    // interior's points and read a halo around it; then the tile's window.
    auto* cached = ctx.frame_cache ? dynamic_cast<StippleFrame*>(ctx.frame_cache->get()) : nullptr;
    std::unique_ptr<StippleFrame> uncached;  // without a frame cache, each tile computes it again
    if (!cached) {
      auto state = std::make_unique<StippleFrame>();
      const gl::Buffer none = gl::make_buffer(4, nullptr, 0);
      if (diffuse && casters_all) {
        const Window nothing;  // every caster into the quadtree, nothing into a fine texture
        win = &nothing;
        hp = hp_other = &none;
        eye_count = eye_cover = &none;
        project_hp = false;
        project_quad = true;
        point_pass("PASS_PROJECT", frame_chunks);
        project_quad = false;
      }
      // Visibility reads `iterations` texels; an eye cell's sums read 2.5
      // cells and its closed coverage 2 x iterations texels beyond.
      const int visibility_halo = int(std::ceil(float(iterations) / f)) + 2;
      const int specular_halo = int(std::ceil(2.5f * eye_cell + 2.0f * float(iterations) / f)) + visibility_halo;
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
      auto chunks_in = [&](const Window& w) {
        reaching.clear();
        for (size_t i = 0; i < frame_chunks.size(); ++i) {
          const Rect& r = chunk_rects[i];
          if (r.min.x < w.px.max.x && r.max.x > w.px.min.x && r.min.y < w.px.max.y && r.max.y > w.px.min.y)
            reaching.push_back(frame_chunks[i]);
        }
        return std::span<const VisibleChunk>(reaching);
      };
      if ((diffuse && !casters_all) || specular)
        for (const Window& w : sweep(visibility_halo)) run_window(w, chunks_in(w), true, nullptr);
      if (diffuse) reduce_quad();
      if (specular) {
        for (const Window& w : sweep(specular_halo)) {
          const std::span<const VisibleChunk> chunks = chunks_in(w);
          run_window(w, chunks, false, nullptr);
          cover_window(w);
          point_pass("PASS_SPECULAR", chunks);
        }
        state->spec_ref = reference();
      }
      state->quad.resize(quad_n);
      glGetNamedBufferSubData(quad.id(), 0, GLsizeiptr(quad_n * 4), state->quad.data());
      state->light_count.resize(light_n);
      glGetNamedBufferSubData(light_count.id(), 0, GLsizeiptr(light_n * 4), state->light_count.data());
      cached = state.get();
      if (ctx.frame_cache)
        *ctx.frame_cache = std::move(state);
      else
        uncached = std::move(state);
    } else {
      glNamedBufferSubData(quad.id(), 0, GLsizeiptr(quad_n * 4), cached->quad.data());
      glNamedBufferSubData(light_count.id(), 0, GLsizeiptr(light_n * 4), cached->light_count.data());
    }
    spec_ref = cached->spec_ref;
    clear_uint(globals, 4, 0);
    run_window(draw_window, ctx.chunks, false, &surface_depth);
    if (specular) cover_window(draw_window);
  }
  win = &draw_window;
  uint32_t visible = 0;
  glGetNamedBufferSubData(globals.id(), 4, 4, &visible);
  // 4. Dots.
  uint32_t kept = 0;
  {
    // Captured dots are read back per chunk, so the capture buffer stays
    // the size of the largest chunk.
    const gl::Program& prog = ctx.shaders->compute("stipples.comp", {"PASS_DRAW"});
    set_uniforms(prog);
    bind_all();
    for (const VisibleChunk& v : ctx.chunks) {
      const uint32_t count = bind_queued_chunk(prog, v, p);
      if (count > 0) glDispatchCompute((count + 127) / 128, 1, 1);
      barrier();
      if (ctx.capture) {
        uint32_t g[4] = {0, 0, 0, 0};
        glGetNamedBufferSubData(globals.id(), 0, 16, g);
        std::vector<glm::vec4> rec(g[3]);
        if (g[3]) glGetNamedBufferSubData(capture.id(), 0, GLsizeiptr(size_t(g[3]) * 16), rec.data());
        for (const glm::vec4& r : rec) {
          CapturedMark m;
          m.point_id = glm::floatBitsToUint(r.w);
          m.center = glm::vec3(r);
          m.direction = glm::vec3(1, 0, 0);
          const float len = glm::length(m.center);
          m.normal = len > 0.0f ? -m.center / len : glm::vec3(0, 0, 1);
          m.length = float(p.get_float("dot_size"));
          m.color = p.get_color("dot_color");
          ctx.capture->push_back(m);
        }
        const uint32_t zero = 0;
        glNamedBufferSubData(globals.id(), 12, 4, &zero);
      }
    }
  }
  glGetNamedBufferSubData(globals.id(), 8, 4, &kept);

  // Resolve: dots over paper into the segment's colour and depth.
  const gl::Program& resolve = ctx.shaders->compute("stipples.comp", {"PASS_RESOLVE"});
  set_uniforms(resolve);
  hp_other = surface_depth;
  bind_all();
  glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  dispatch_rect(resolve, clip);
  gl::check_gl("stipples");
  if (ctx.stats) {
    // In tiles, the points of each tile's halo are counted again.
    (*ctx.stats)["stipples_visible"] += double(visible);
    (*ctx.stats)["stipples_drawn"] += double(kept);
  }
}

const MarkRegistration registration{{
    Schema{"stipples",
           "Stipples",
           "Stippling without normals (seed 003): hidden points removed in image space, shading by the density "
           "of dots (a light-view min-depth quadtree thins lit surfaces; point counts seen from eye and light "
           "open highlights).",
           {
               float_param("dot_size", 2.0, 0.5, 16.0, "px", "Dot diameter"),
               float_param("size_jitter", 0.0, 0.0, 1.0, "", "Random size variation per dot (seeded by the point id)"),
               color_param("dot_color", {0.0, 0.0, 0.0, 1.0}, "Dot colour (display sRGB; alpha: its opacity)"),
               color_param("paper_color", {1.0, 1.0, 1.0, 1.0},
                           "Colour under the dots where the surface is (alpha: its opacity; 0 leaves dots only)"),
               int_param("iterations", 3, 0, 32, "",
                         "Hidden points: how many times each texel takes its neighbours' depths (closes holes "
                         "between front points of this many texels)"),
               float_param("depth_offset", 0.038, 0.0, 0.5, "",
                           "Hidden points: depth added per spreading step and kept in front of the surface, as a "
                           "fraction of the segment's view depth range (the paper's 'slightly larger depth')"),
               float_param("resolution_factor", 1.25, 1.0, 4.0, "",
                           "Hidden-point texture size over the screen's (larger: fewer front points lost where "
                           "they crowd, more iterations needed)"),
               light_space_param(),
               light_azimuth_param(135.0),
               light_elevation_param(50.0),
               bool_param("diffuse", true, "Thin lit surfaces by the light-view quadtree"),
               only_when(float_param("level", 7.0, 0.0, 11.0, "",
                                     "Quadtree LEVEL: 2^LEVEL cells across the segment seen from the light; the point "
                                     "closest to the light in each is hidden (higher: more cells, lit areas thinner; "
                                     "fractions blend adjacent levels point by point)"),
                         "diffuse", {"true"}),
               only_when(enum_param("level_scale", {"absolute", "point_count"}, 0,
                                    "absolute: LEVEL as given (the paper's); point_count: LEVEL for 16384 points, "
                                    "plus log4 of the segment's point count over that, so sparse and dense scans "
                                    "thin alike"),
                         "diffuse", {"true"}),
               only_when(enum_param("shadow_casters", {"all", "visible"}, 0,
                                    "Points the light sees: all (hidden ones too, so surfaces behind others from the "
                                    "light stay dense: shadows) or only the visible ones (as the paper's text)"),
                         "diffuse", {"true"}),
               bool_param("specular", false, "Open highlights where the surface faces between eye and light"),
               only_when(float_param("tau", 0.2, 0.0, 1.0, "",
                                     "Highlight threshold: points whose normalised difference from the brightest "
                                     "area per point is below tau may be hidden (more below: more often)"),
                         "specular", {"true"}),
               only_when(float_param("specular_cell", 8.0, 2.0, 64.0, "px",
                                     "Size of the cells points are counted in, on screen (the light's cells are as "
                                     "large in scene units at the segment's middle depth)"),
                         "specular", {"true"}),
               density_mode_param(),
               queue_level_param(0.1),
               int_param("seed", 0, 0, 65535, "", "Varies every random choice (still fixed per point)"),
           }},
    [] { return std::make_unique<Stipples>(); }}};

}  // namespace
}  // namespace pointnpr
