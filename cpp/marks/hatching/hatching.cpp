// Art-directable hatching of point clouds (seed 002, Wagner et al.): every
// point kept is replaced by one or two surface-aligned, textured line quads.
//
//  - X-Toon (Barla et al. 2006): texture coordinates (brightness from the
//    light and the point normal, depth over the segment); its alpha drives
//    lighting by omission (a point survives with probability alpha x
//    density) and the cross-hatch probability (alpha x h); its colour feeds
//    the colouring modes. Procedural textures for the paper's looks, or any
//    image.
//  - Probabilistic interpolation seeded by the point id: omission, cross vs
//    parallel, pencil choice, jitter of alpha, length, position and angle
//    are per-point hashes, so a point decides the same in every frame.
//  - Survivors are compacted per workgroup in point order and drawn by
//    indirect draws: the rasterizer sees only strokes that are drawn.
//  - Lines: d1 = u - (u.n) n from a user direction, d2 = n x d1; length
//    shortened by curvature; widths below 1.5 px are drawn at 1.5 px with
//    proportionally less alpha (thin quads would otherwise shimmer).
//  - Colouring: constant, X-Toon, point colour blended with X-Toon; hue
//    shift; pencil quantization (two nearest pencil hues mixed by
//    probabilistic interpolation, then black and white to match value and
//    saturation, section 3.3).
//  - Depth pass: every point as a disc into depth only; strokes then drawn
//    with the depth test, no depth writes, moved toward the camera by
//    `depth_offset` disc radii (the paper's polygon offset, in scene units
//    so it holds at any depth; on a surface steeper than that offset allows,
//    by its slope, up to twice as many: camera-facing discs stand in front
//    of a steep surface by a radius x its slope). Strokes blend order-independently (weighted
//    average colour, product of transmittances, minimum depth: sums and
//    products in a fixed primitive order, so the bytes never vary).
//  - What the paper left open: strokes past the silhouette are clipped to
//    the depth pass (`clip_to_surface`); the paper fills the surface under
//    the strokes (`paper_color`, alpha = its opacity), so the segment hides
//    what is behind it when compositing; points without a usable normal
//    draw view-facing strokes.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <glm/gtc/type_ptr.hpp>
#include <mutex>

#include "core/error.h"
#include "core/image_io.h"
#include "core/sparse_growth.h"
#include "gl/device.h"
#include "marks/hatching/hatching.h"
#include "render/backend.h"
#include "marks/points/points.h"
#include "render/exact_raster.h"
#include "render/ink_layer.h"
#include "render/image_textures.h"
#include "scene/camera.h"

namespace pointnpr {
namespace {

using hatching::Stroke;

constexpr uint32_t kBatchPoints = 1u << 18;  // stroke records per batch (16 MiB)
constexpr int kMaxPencils = 64;
static_assert(sizeof(hatching::HatchingSettings::pencils) == kMaxPencils * sizeof(glm::vec4));
// Neighbours of the local resolution that estimates the surface area per
// point (stroke_coverage): with k neighbours within R and mean distance
// 2R/3 on a surface, the area per point is pi (1.5 r)^2 / k ~ 0.88 r^2 at k = 8.
constexpr int kSpacingNeighbors = 8;

// Pencil boxes (display sRGB), saturated and bright as coloured pencils are.
const std::vector<glm::vec3>& pencil_box(int which) {
  static const std::vector<glm::vec3> box12 = {
      {0.86f, 0.13f, 0.15f}, {0.95f, 0.42f, 0.10f}, {0.98f, 0.78f, 0.10f}, {0.60f, 0.80f, 0.15f},
      {0.13f, 0.62f, 0.30f}, {0.10f, 0.65f, 0.62f}, {0.12f, 0.55f, 0.85f}, {0.15f, 0.25f, 0.75f},
      {0.45f, 0.20f, 0.70f}, {0.80f, 0.25f, 0.65f}, {0.93f, 0.40f, 0.55f}, {0.55f, 0.33f, 0.18f}};
  static const std::vector<glm::vec3> box24 = [] {
    std::vector<glm::vec3> out;
    for (int i = 0; i < 24; ++i) {
      // Evenly spaced hues, alternating full and slightly muted saturation.
      const float h = float(i) / 24.0f * 6.0f, s = i % 2 ? 0.75f : 0.9f, v = i % 3 == 2 ? 0.8f : 0.95f;
      const float c = v * s, x = c * (1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f)), m = v - c;
      glm::vec3 rgb = h < 1 ? glm::vec3(c, x, 0) : h < 2 ? glm::vec3(x, c, 0) : h < 3 ? glm::vec3(0, c, x)
                    : h < 4 ? glm::vec3(0, x, c) : h < 5 ? glm::vec3(x, 0, c) : glm::vec3(c, 0, x);
      out.push_back(rgb + m);
    }
    return out;
  }();
  return which == 0 ? box12 : box24;
}

float hue_of(glm::vec3 c) {
  const float mx = std::max({c.r, c.g, c.b}), mn = std::min({c.r, c.g, c.b}), d = mx - mn;
  if (d <= 0.0f) return 0.0f;
  float h = mx == c.r ? std::fmod((c.g - c.b) / d, 6.0f) : mx == c.g ? (c.b - c.r) / d + 2.0f : (c.r - c.g) / d + 4.0f;
  if (h < 0.0f) h += 6.0f;
  return h / 6.0f;
}

class Hatching final : public Mark {
 public:
  AttributeSet attributes(const ParamValues& p) const override {
    const int k = p.get_int("normal_neighbors");
    AttributeSet set{{AttributeKind::PointId}, {AttributeKind::Normal, k}};
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    if (p.get_float("curvature_length") > 0.0) set.insert({AttributeKind::Curvature, k});
    if (p.get_float("stroke_coverage") > 0.0) set.insert({AttributeKind::LocalResolution, kSpacingNeighbors});
    if (p.get_bool("opacity_draws")) set.insert({AttributeKind::SplatOpacity});
    if (p.get_enum_name("coloring") == "point") {
      const AttributeSet colors = color_attributes(ColorSource(p.get_enum("color_source")));
      set.insert(colors.begin(), colors.end());
    }
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override {
    // Half a stroke (longest: jittered length, moved by the position jitter)
    // plus its width, around each point; with a coverage, a stroke where the
    // points are too sparse for it grows up to 3x (hatching_kernels.glsl).
    const bool irregular = p.get_enum_name("placement") == "irregular";
    const double grow = p.get_float("stroke_coverage") > 0.0 && p.get_bool("grow_sparse_strokes") ? kMaxSparseGrowth : 1.0;
    const double reach =
        grow * (1.0 + p.get_float("length_jitter")) * (0.5 + (irregular ? p.get_float("position_jitter") : 0.0));
    MarkExtent e;
    // Depth discs in scene units are capped on screen as splats are.
    const float disc_px = p.get_enum_name("depth_disc") == "pixels"
                              ? float(std::max(p.get_float("depth_size"), 1.0)) * 0.5f
                              : kMaxSplatPixels * 0.5f;
    if (p.get_enum_name("units") == "world") {
      e.world = reach * p.get_float("world_length") + grow * p.get_float("world_width");
      e.pixels = disc_px + 2.0f;  // depth discs and the 1.5 px minimum width
    } else {
      e.pixels = float(reach * p.get_float("line_length") + grow * p.get_float("line_width")) + 2.0f + disc_px;
    }
    return e;
  }

  void draw(const MarkContext& ctx, const ParamValues& p) const override;
  // What both stroke backends draw with this frame.
  hatching::StrokePass resolve(const MarkContext& ctx, const ParamValues& p) const;
  void draw_strokes_gl(const MarkContext& ctx, const ParamValues& p, const hatching::StrokePass& pass) const;

  // Every stroke is placed and textured from its frame pixel
  // (render/exact_raster.h) and every choice is per point (the depth range
  // is the frame's): a tile is the bytes of the frame. In pixel units a
  // stroke is cut at stroke_reach() from its centre, its extent; in scene
  // units the chunks' bounds grown by the stroke's reach in scene units
  // bound it on screen, so every tile it reaches draws it. No pass reads
  // neighbouring pixels.
  bool draws_tiles(const ParamValues&) const override { return true; }

 private:
  // Pixels from its centre a stroke in pixel units may cover: half the
  // longest jittered length and half the width (at least the 1.5 px drawn),
  // plus one for perspective (a stroke turned toward the camera projects
  // its near half a little longer; farther than this it is cut).
  static float stroke_reach(const ParamValues& p) {
    return float(0.5 * (1.0 + p.get_float("length_jitter")) * p.get_float("line_length") +
                 0.5 * std::max(p.get_float("line_width"), 1.5) + 1.0);
  }

  // The depth pass's disc: by default a multiple of the scan's own median
  // spacing, so the discs close the surface at any density and zoom (a
  // fixed pixel size leaves gaps on sparse scans, where back strokes show
  // and front strokes are cut into crosses). The frame's chunks, not the
  // tile's: every tile draws the same discs.
  struct DepthDisc {
    bool world = false;
    float diameter = 4.0f;
  };
  static DepthDisc depth_disc(const MarkContext& ctx, const ParamValues& p) {
    const std::string mode = p.get_enum_name("depth_disc");
    if (mode == "world") return {true, float(p.get_float("depth_world_size"))};
    if (mode == "spacing") {
      float spacing = 0.0f;
      const GpuCloud* last = nullptr;
      for (const VisibleChunk& v : ctx.frame_chunks.empty() ? ctx.chunks : ctx.frame_chunks) {
        if (v.gpu == last) continue;  // a cloud's chunks are consecutive
        last = v.gpu;
        spacing = std::max(spacing, median_spacing(v, kSpacingNeighbors, 0.0f));
      }
      if (spacing > 0.0f) return {true, float(p.get_float("depth_spacing")) * spacing};
    }
    return {false, float(p.get_float("depth_size"))};
  }

  struct Palette {
    std::filesystem::file_time_type modified;
    std::vector<glm::vec3> colors;
  };
  const std::vector<glm::vec3>& pencils(const ParamValues& p) const;
  mutable std::mutex palette_mutex_;
  mutable std::map<std::string, Palette> palettes_;
};

const std::vector<glm::vec3>& Hatching::pencils(const ParamValues& p) const {
  const std::string set = p.get_enum_name("pencil_set");
  if (set != "image") return pencil_box(set == "box_12" ? 0 : 1);
  const std::string& path = p.get_path("pencil_image");
  if (path.empty()) throw ParameterError("hatching: pencil_set 'image' needs a pencil_image");
  std::lock_guard lock(palette_mutex_);
  std::error_code ec;
  const auto modified = std::filesystem::last_write_time(path, ec);
  Palette& palette = palettes_[path];
  if (palette.colors.empty() || palette.modified != modified) {
    // Every distinct pixel colour of the image is a pencil (a strip of
    // swatches, or any small picture), at most kMaxPencils of them.
    const Image image = to_rgba(read_image(path));
    std::vector<glm::vec3> colors;
    for (size_t i = 0; i + 3 < image.pixels.size(); i += 4) {
      const glm::vec3 c = glm::clamp(glm::vec3(image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]), 0.0f, 1.0f);
      if (std::none_of(colors.begin(), colors.end(), [&](glm::vec3 o) { return glm::all(glm::lessThan(glm::abs(o - c), glm::vec3(1.0f / 512.0f))); }))
        colors.push_back(c);
      if (colors.size() > size_t(kMaxPencils))
        throw ParameterError("hatching: pencil_image '" + path + "' has more than " + std::to_string(kMaxPencils) +
                             " colours; give a strip of swatches");
    }
    if (colors.empty()) throw ParameterError("hatching: pencil_image '" + path + "' has no pixels");
    palette = {modified, std::move(colors)};
  }
  return palette.colors;
}

hatching::StrokePass Hatching::resolve(const MarkContext& ctx, const ParamValues& p) const {
  const Camera& cam = *ctx.camera;
  const glm::ivec2 size = frame_size(ctx.targets);  // the projection's
  const bool world_units = p.get_enum_name("units") == "world";
  const bool depth_pass = p.get_bool("depth_pass");
  const float px_per_unit = float(cam.pixels_per_unit(1.0, size.y));

  // Directions in view space, composed in double.
  const glm::dmat3 view_from_world(cam.view_from_world);
  const glm::vec3 light_view = view_light_direction(p, cam);
  const glm::vec3 dir_view(glm::normalize(view_from_world * world_direction(p.get_float("direction_azimuth"),
                                                                         p.get_float("direction_elevation"))));

  const std::vector<glm::vec3>* pencil_colors = nullptr;
  std::vector<std::pair<float, glm::vec3>> by_hue;
  if (p.get_bool("pencil_quantize") && applies(*p.schema().find("pencil_quantize"), p)) {
    pencil_colors = &pencils(p);
    for (const glm::vec3& c : *pencil_colors) by_hue.push_back({hue_of(c), c});
    std::sort(by_hue.begin(), by_hue.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : a.second.r < b.second.r;
    });
  }

  hatching::StrokePass pass;
  if (p.get_enum_name("xtoon") == "image") {
    const std::string& path = p.get_path("xtoon_image");
    if (path.empty()) throw ParameterError("hatching: xtoon 'image' needs an xtoon_image");
    pass.xtoon_image = &ctx.images->get(path, "xtoon", ImageTextures::Sampling::Clamped, [](Image i) { return i; });
  }

  hatching::HatchingSettings& u = pass.select;
  u.light_dir = glm::vec4(light_view, 0.0f);
  u.direction = glm::vec4(dir_view, 0.0f);
  u.constant_color = glm::vec4(p.get_color("stroke_color"));
  for (size_t i = 0; i < by_hue.size(); ++i) u.pencils[i] = glm::vec4(by_hue[i].second, by_hue[i].first);
  u.ortho = cam.orthographic ? 1 : 0;
  u.near_plane = float(cam.clip_start);
  u.far_plane = float(cam.clip_end);
  u.depth_min = float(ctx.depth_min);
  u.depth_max = float(ctx.depth_max);
  u.px_per_unit = px_per_unit;
  u.ambient = float(p.get_float("ambient"));
  u.specular = float(p.get_float("specular"));
  u.two_sided = p.get_bool("two_sided") ? 1 : 0;
  u.shininess = float(p.get_float("shininess"));
  u.xtoon = p.get_enum("xtoon");
  u.density = float(p.get_float("density"));
  u.cross_share = float(p.get_float("cross_hatch"));
  u.coverage = float(p.get_float("stroke_coverage"));
  u.grow_sparse = p.get_bool("grow_sparse_strokes") ? 1 : 0;
  u.world_units = world_units ? 1 : 0;
  u.stroke_length = float(world_units ? p.get_float("world_length") : p.get_float("line_length"));
  u.stroke_width = float(world_units ? p.get_float("world_width") : p.get_float("line_width"));
  u.length_jitter = float(p.get_float("length_jitter"));
  u.curvature_length = float(p.get_float("curvature_length"));
  const bool irregular = p.get_enum_name("placement") == "irregular";
  u.position_jitter = irregular ? float(p.get_float("position_jitter")) : 0.0f;
  u.angle_jitter = irregular ? float(glm::radians(p.get_float("angle_jitter"))) : 0.0f;
  u.coloring = p.get_enum("coloring");
  u.point_blend = float(p.get_float("point_blend"));
  u.color_tone = p.get_enum_name("coloring") == "point" ? float(p.get_float("color_tone")) : 0.0f;
  u.hue_shift = float(p.get_float("hue_shift") / 360.0);
  u.pencil_count = int(by_hue.size());
  u.opacity = float(p.get_float("opacity"));
  u.alpha_modification = float(p.get_float("alpha_modification"));
  u.alpha_jitter = float(p.get_float("alpha_jitter"));
  u.seed = uint32_t(p.get_int("seed"));

  hatching::HatchingRasterSettings& rs = pass.raster;
  rs.projection = glm::mat4(cam.projection);
  rs.inv_projection = glm::mat4(glm::inverse(cam.projection));
  rs.size_x = size.x;
  rs.size_y = size.y;
  rs.ortho = cam.orthographic ? 1 : 0;
  rs.near_plane = float(cam.clip_start);
  rs.far_plane = float(cam.clip_end);
  rs.px_per_unit = px_per_unit;
  // The offset toward the camera, in depth-disc radii (scene units; on a
  // steep surface more: hatching_quad.glsl).
  rs.offset_radii = depth_pass ? float(p.get_float("depth_offset")) : 0.0f;
  const DepthDisc disc = depth_disc(ctx, p);
  rs.disc_world = disc.world ? 1 : 0;
  rs.disc_size = disc.diameter;
  rs.max_reach = world_units ? std::numeric_limits<float>::max() : stroke_reach(p);
  rs.stroke_texture = p.get_enum("stroke_texture");
  rs.clip_to_surface = depth_pass && p.get_bool("clip_to_surface") ? 1 : 0;

  pass.depth_pass = depth_pass;
  pass.discs.world_size = disc.world;
  pass.discs.point_size = disc.diameter;
  pass.discs.world_diameter = disc.diameter;
  pass.paper = p.get_color("paper_color");
  pass.normal_k = p.get_int("normal_neighbors");
  pass.spacing_k = kSpacingNeighbors;
  pass.opacity_draws = p.get_bool("opacity_draws");
  pass.color_source = ColorSource(p.get_enum("color_source"));
  return pass;
}

void Hatching::draw(const MarkContext& ctx, const ParamValues& p) const {
  const hatching::StrokePass pass = resolve(ctx, p);
  if (chosen_backend(p) == Backend::Native) {
    hatching::draw_strokes_native(ctx, p, pass);
  } else {
    draw_strokes_gl(ctx, p, pass);
  }
}

// The depth pass; then per batch of points, a compute pass decides each
// point's strokes, and 12 vertices per kept point expand them.
void Hatching::draw_strokes_gl(const MarkContext& ctx, const ParamValues& p, const hatching::StrokePass& pass) const {
  // Depth pass: discs into the GL depth buffer and the linear depth image.
  if (pass.depth_pass) draw_splats_gl(ctx, pass.discs);
  const InkLayer ink(ctx, "hatching");
  const int k = pass.normal_k;
  const hatching::HatchingSettings& u = pass.select;
  const hatching::HatchingRasterSettings& rs = pass.raster;
  // Record slots: 128 per workgroup (each compacts its survivors to the
  // front of its slots and issues one indirect draw of them).
  // Continuous resolution queue (render/mark.h): a chunk's first
  // queue_count() points of its queue order (all of them when off).
  auto slots_of = [&p](const VisibleChunk& v) { return (queue_count(v, p) + 127u) / 128u * 128u; };
  uint32_t largest = 0;
  for (const VisibleChunk& v : ctx.chunks) largest = std::max(largest, slots_of(v));
  const uint32_t capacity = std::max(kBatchPoints, largest);
  const gl::Buffer& strokes = ctx.targets.scratch_buffer(size_t(capacity) * sizeof(Stroke), 0);
  const gl::Buffer& commands = ctx.targets.scratch_buffer(size_t(capacity / 128u) * sizeof(DrawCommand), 1);
  const uint32_t zero2[2] = {0, 0};
  const gl::Buffer counters = gl::make_buffer(sizeof(zero2), zero2, GL_DYNAMIC_STORAGE_BIT);

  const gl::Program& select = ctx.shaders->compute("hatching_select.comp");
  select.use();
  gl::check_uniform_block(select, "HatchingSettings", sizeof(u), 0);
  const gl::Buffer settings = gl::make_buffer(sizeof(u), &u);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, settings.id());
  glUniform4fv(select.location("u_constant_color"), 1, glm::value_ptr(u.constant_color));
  glUniform1i(select.location("u_xtoon_image"), 0);
  glBindTextureUnit(0, pass.xtoon_image ? pass.xtoon_image->id() : ink.accum.id());

  const gl::Program& expand = ctx.shaders->graphics("hatching_strokes.vert", "hatching_strokes.frag");
  expand.use();
  gl::check_uniform_block(expand, "HatchingRasterSettings", sizeof(rs), 1);
  const gl::Buffer raster_settings = gl::make_buffer(sizeof(rs), &rs);
  glBindBufferBase(GL_UNIFORM_BUFFER, 1, raster_settings.id());
  glUniform1i(expand.location("u_surface_depth"), 1);
  glBindTextureUnit(1, ctx.targets.depth->id());
  // Tiles: corners at their exact frame positions, each fragment's place on
  // the stroke from its frame pixel's ray (render/exact_raster.h).
  const ExactRaster raster = exact_raster(ctx.targets, extent(p).pixels);
  raster.set_uniforms(expand);

  const std::vector<RecordBatch> batches =
      record_batches(ctx.chunks.size(), capacity, [&](size_t c) { return slots_of(ctx.chunks[c]); });
  for (const RecordBatch& batch : batches) {
    if (batch.begin > 0) glFinish();  // the previous batch's draw has read the records
    select.use();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, strokes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, counters.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, commands.id());
    const GpuCloud* median_of = nullptr;
    float median = 0.0f;  // median_luminance of median_of's colours
    for (size_t c = batch.begin; c < batch.end; ++c) {
      const VisibleChunk& v = ctx.chunks[c];
      const GpuCloud& g = *v.gpu;
      bind_chunk(select, v, pass.color_source,
                 {{2, g.find({AttributeKind::Normal, k})}, {3, g.find({AttributeKind::Curvature, k})},
                  {6, g.find({AttributeKind::PointId})},
                  {9, g.find({AttributeKind::LocalResolution, kSpacingNeighbors})},
                  {11, pass.opacity_draws ? g.find({AttributeKind::SplatOpacity}) : nullptr}});
      glUniform1i(select.location("u_has_opacity"), pass.opacity_draws ? 1 : 0);
      if (pass.select.coloring == 2 && &g != median_of) {  // once per cloud
        median_of = &g, median = 0.0f;
        if (const auto cloud = g.source.lock())
          median = median_luminance(g, *cloud, host_colors(g, *cloud, pass.color_source, pass.select.constant_color));
      }
      glUniform1f(select.location("u_color_median"), median);
      glUniform1i(select.location("u_has_spacing"),
                  g.find({AttributeKind::LocalResolution, kSpacingNeighbors}) ? 1 : 0);
      glUniform1ui(select.location("u_out_base"), batch.offsets[c - batch.begin]);
      glUniform1ui(select.location("u_command_base"), batch.offsets[c - batch.begin] / 128u);
      glUniform1i(select.location("u_has_curvature"), g.find({AttributeKind::Curvature, k}) ? 1 : 0);
      const uint32_t count = queue_count(v, p);
      glUniform1i(select.location("u_queue"), draws_queue(v, p) ? 1 : 0);
      if (draws_queue(v, p)) {
        const gl::Buffer* order = g.find({AttributeKind::QueueOrder});
        if (!order) throw GLError("hatching: the queue order was not uploaded");
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, order->id());
        glUniform1ui(select.location("u_count"), count);
      }
      if (count > 0) glDispatchCompute((count + 127) / 128, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);

    ink.begin(pass.depth_pass, raster);
    expand.use();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, strokes.id());
    draw_record_batch(commands, batch);
    ink.end();
    gl::check_gl("hatching strokes");
    if (ctx.capture)
      for (const Stroke& s : drawn_records<Stroke>(strokes, commands, batch, 12)) ctx.capture->push_back(captured(s));
  }

  // 3. Resolve: ink over paper, the surface's depth (else the strokes').
  ink.resolve(pass.paper, pass.depth_pass);

  uint32_t counts[2] = {0, 0};
  glGetNamedBufferSubData(counters.id(), 0, sizeof(counts), counts);
  if (ctx.stats) {
    (*ctx.stats)["strokes_drawn"] += double(counts[0]);
    (*ctx.stats)["strokes_crossed"] += double(counts[1]);
  }
}

const MarkRegistration registration{{
    Schema{"hatching",
           "Hatching",
           "Replaces points by surface-aligned pencil strokes whose density, crossing and colour follow the light "
           "through an X-Toon texture (Wagner et al., art-directable hatching of point clouds).",
           {
               enum_param("xtoon", {"pencil", "wax_crayon", "two_colored", "chalk", "ink", "image"}, 0,
                          "X-Toon texture (x: brightness, y: depth): alpha = how many strokes survive, colour = "
                          "their colour in the xtoon colouring modes"),
               only_when(image_param("xtoon_image", "Your own X-Toon texture (x: brightness dark to lit, y: depth "
                                                    "near to far; alpha: stroke survival)"),
                         "xtoon", {"image"}),
               float_param("density", 1.0, 0.0, 1.0, "", "Fraction of strokes kept (times the X-Toon alpha)"),
               float_param("stroke_coverage", 1.5, 0.0, 16.0, "",
                           "Keeps at most enough strokes to cover the surface this many times over, from each "
                           "point's spacing (dense or irregular scans get the same stroke density; 0: off, every "
                           "point may draw)"),
               added_later(bool_param("grow_sparse_strokes", true,
                                      "Where the points are too sparse on screen for the stroke coverage (a near or "
                                      "sparse surface), strokes grow, length and width alike, up to 3x, so the tone "
                                      "holds at any density (with stroke_coverage above 0)"),
                           {0.0}),
               float_param("cross_hatch", 0.5, 0.0, 1.0, "",
                           "Cross-hatch proportion h: a point draws a crossing second line with probability "
                           "X-Toon alpha x h (0: parallel hatching only)"),
               enum_param("units", {"pixels", "world"}, 0, "Line length and width in pixels or in scene units"),
               only_when(float_param("line_length", 14.0, 1.0, 256.0, "px", "Stroke length"), "units", {"pixels"}),
               only_when(float_param("line_width", 1.2, 0.25, 16.0, "px", "Stroke width"), "units", {"pixels"}),
               only_when(float_param("world_length", 0.05, 0.0001, 100.0, "m", "Stroke length"), "units", {"world"}),
               only_when(float_param("world_width", 0.004, 0.00001, 10.0, "m", "Stroke width"), "units", {"world"}),
               float_param("length_jitter", 0.3, 0.0, 1.0, "", "Random length factor per stroke (hand-drawn lengths)"),
               float_param("curvature_length", 0.6, 0.0, 1.0, "",
                           "How much strokes shorten where the surface curves: at a surface variation of 0.05 (creases, "
                           "corners) to 1 - 0.85 x this; the tone stays (more strokes kept where the coverage limit "
                           "thins them, then more crossings). 0: off, no curvature computed"),
               enum_param("placement", {"regular", "irregular"}, 0,
                          "regular: strokes centred on their points along d1; irregular: seeded jitter of position "
                          "and angle"),
               only_when(float_param("position_jitter", 0.4, 0.0, 2.0, "", "Shift of each stroke, in stroke lengths"),
                         "placement", {"irregular"}),
               only_when(float_param("angle_jitter", 20.0, 0.0, 90.0, "deg", "Turn of each stroke around its normal"),
                         "placement", {"irregular"}),
               float_param("direction_azimuth", 30.0, -180.0, 180.0, "deg",
                           "Line direction u, projected onto each point's tangent plane: angle around the world Z axis"),
               float_param("direction_elevation", 35.0, -90.0, 90.0, "deg", "Line direction u: angle above the XY plane"),
               // A key light with the camera and normals toward it by default: a world light and
               // the scan's own normal orientation left Y-down depth frames lit from below and
               // whole objects flipping between lit and shaded (files saved before keep both).
               default_changed(light_space_param(1), {0.0}),
               light_azimuth_param(135.0),
               light_elevation_param(50.0),
               default_changed(bool_param("two_sided", true,
                                          "Light normals turned toward the camera (for scans whose normals are "
                                          "not consistently oriented; strokes at silhouettes may change as the "
                                          "camera moves)"),
                               {0.0}),
               float_param("ambient", 0.0, 0.0, 1.0, "", "Brightness every surface gets"),
               float_param("specular", 0.0, 0.0, 1.0, "",
                           "The Phong highlight's share of the light (the rest is diffuse, so the highlight shows "
                           "where the diffuse light alone would already be at full brightness)"),
               only_when(float_param("shininess", 16.0, 1.0, 256.0, "", "Phong exponent of the highlight"),
                         "specular", {"nonzero"}),
               enum_param("coloring", {"constant", "xtoon", "point"}, 0,
                          "constant: the stroke colour; xtoon: the X-Toon texture's; point: the point's colour "
                          "blended with the X-Toon colour"),
               only_when(color_param("stroke_color", {0.13, 0.13, 0.16, 1.0}, "Stroke colour (display sRGB)"),
                         "coloring", {"constant"}),
               only_when(float_param("point_blend", 0.3, 0.0, 1.0, "", "How much the X-Toon colour tints the point colour"),
                         "coloring", {"point"}),
               only_when(added_later(float_param("color_tone", 1.0, 0.0, 1.0, "",
                                                 "How much the point colour's darkness is tone: the X-Toon "
                                                 "brightness times mix(1, its luminance over the scan's median, "
                                                 "this), so a dark colour in the light still gets dense strokes, as "
                                                 "a coloured-pencil drawing gives it"),
                                     {0.0}),
                         "coloring", {"point"}),
               only_when(color_source_param(), "coloring", {"point"}),
               float_param("hue_shift", 0.0, -180.0, 180.0, "deg", "Hue rotation of the stroke colour"),
               // A constant colour is chosen as it is wanted (and the default, a
               // grey, has no hue to match): pencils match the scan's or X-Toon's.
               only_when(bool_param("pencil_quantize", false,
                                    "Only colours of a pencil set: the two nearest hues mixed by chance, then black "
                                    "and white for value and saturation"),
                         "coloring", {"point", "xtoon"}),
               only_when(enum_param("pencil_set", {"box_12", "box_24", "image"}, 1,
                                    "Pencil colours: 12 or 24 pencils, or the distinct colours of an image"),
                         "pencil_quantize", {"true"}),
               only_when(image_param("pencil_image", "Pencil colours: every distinct pixel colour (at most 64)"),
                         "pencil_set", {"image"}),
               float_param("opacity", 0.85, 0.0, 1.0, "", "Stroke opacity"),
               float_param("alpha_modification", 1.0, 0.0, 1.0, "",
                           "How much lighter strokes get where the X-Toon alpha is low (pencil pressure)"),
               float_param("alpha_jitter", 0.3, 0.0, 1.0, "", "Random opacity variation per stroke"),
               enum_param("stroke_texture", {"pencil", "crayon", "ink", "soft"}, 0,
                          "Texture of a stroke: graphite with grain, waxy crayon, solid ink, soft dot"),
               paper_color_param({0.97, 0.96, 0.92, 1.0}, "strokes"),
               bool_param("depth_pass", true, "Hide strokes behind the surface: all points as discs into depth first"),
               enum_param("depth_disc", {"spacing", "pixels", "world"}, 0,
                          "Size of the depth-pass discs: from the scan's median point spacing (closes the surface "
                          "at any density and zoom), in pixels, or in scene units"),
               only_when(float_param("depth_spacing", 2.0, 0.5, 8.0, "",
                                     "Diameter of the depth-pass discs in median spacings (mean distance to a "
                                     "point's 8 nearest neighbours)"),
                         "depth_disc", {"spacing"}),
               only_when(float_param("depth_size", 4.0, 0.5, 32.0, "px", "Diameter of the depth-pass discs"),
                         "depth_disc", {"pixels"}),
               only_when(float_param("depth_world_size", 0.03, 0.0001, 100.0, "m", "Diameter of the depth-pass discs"),
                         "depth_disc", {"world"}),
               only_when(float_param("depth_offset", 2.0, 0.0, 10.0, "",
                                     "Strokes moved toward the camera by this many disc radii (polygon offset), "
                                     "on a steep surface by its slope (tan of its angle to the view), up to twice "
                                     "as many; 0 lets discs cut the strokes"),
                         "depth_pass", {"true"}),
               only_when(bool_param("clip_to_surface", true, "Cut strokes where they leave the surface's silhouette"),
                         "depth_pass", {"true"}),
               int_param("normal_neighbors", 16, 3, 64, "",
                         "Neighbours normals and curvature are estimated from where a cloud has none (PCA)"),
               int_param("seed", 0, 0, 65535, "", "Varies every random choice (still fixed per point)"),
               density_mode_param(),
               queue_level_param(0.05),
               rasterizer_param("gl: the GL passes (a compute pass selects, instanced quads draw); native: the same "
                                "kernels on the CPU's threads (the same images but for the last bits of pow, exp and "
                                "sin, and rare coverage ties)"),
               bool_param("opacity_draws", false,
                          "A Gaussian-splat capture's opacity scales each splat's odds of strokes (its faint haze "
                          "gets few; plain points: unchanged)"),
           }},
    [] { return std::make_unique<Hatching>(); }}};

}  // namespace
}  // namespace pointnpr
