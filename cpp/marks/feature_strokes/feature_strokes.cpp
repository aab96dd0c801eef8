// Feature-point strokes (seed 001, Xu et al., sections 5 to 7): the points
// of high feature degree and a dithered share of the others become point
// sprites, line segments or textured strokes.
//
//  - Feature points: feature degree (geometry/features, section 5.2 on
//    points) above `feature_threshold`. Dithering points (section 5.2): a
//    non-feature point is kept when a seeded per-point value (hash of its
//    id) is below dither x (r / r_median)^2 x tone, r its local resolution:
//    sparse scans (far from the scanner) keep more of their points, so the
//    dithering points are uniform in 3D (the paper's range-aware dithering
//    for unorganised clouds); tone: darker points more likely.
//  - Directional vs non-directional (section 5.3): the eq. 2 line fit of
//    each feature point's nearest feature points (AttributeKind::
//    FeatureLine); error below `line_error` = directional, with the fitted
//    3D direction projected on screen; otherwise (and for dithering points)
//    a constant screen direction.
//  - Primitives per class: point sprites (Gaussian kernel), line segments,
//    textured strokes (quads along the projected direction, Fig. 5 texture
//    coordinates, alpha stroke textures: procedural or any image).
//  - Two-pass visibility splatting (section 6.1): pass 1 draws every point
//    as an opaque disc of its local resolution's projected size (hole-free)
//    into depth, pushed away along the view ray by `depth_offset` local
//    resolutions; pass 2 draws the primitives with the depth test and no
//    depth writes, blended order-independently (weighted-average colour,
//    product of transmittances, minimum depth, as the hatching mark; its
//    resolve pass puts ink over paper).
//  - Continuous resolution queue (sections 6.3, 7.2; render/mark.h): with
//    density_mode = constant_on_screen each chunk draws only the first
//    queue_level x M points of its seeded order (M: its projected area), so
//    stroke density on screen is constant as the camera moves and a step
//    adds or removes points at the end of the queue only. Pass 1 keeps
//    every point (visibility stays hole-free).
#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <limits>

#include "core/error.h"
#include "core/image_io.h"
#include "core/sparse_growth.h"
#include "geometry/analysis.h"
#include "marks/feature_strokes/feature_strokes.h"
#include "render/backend.h"
#include "render/exact_raster.h"
#include "render/image_textures.h"
#include "render/mark.h"
#include "render/ink_layer.h"
#include "scene/point_cloud.h"
#include "scene/camera.h"

namespace pointnpr {
namespace {

// GPU record of one primitive (std430, 64 bytes; feature_strokes_common.glsl).
using feature_strokes::Record;

constexpr uint32_t kBatchPoints = 1u << 18;  // records per batch (16 MiB)
constexpr int kResolutionNeighbors = kStrokeResolutionNeighbors;

class FeatureStrokes final : public Mark {
 public:
  AttributeSet attributes(const ParamValues& p) const override {
    const int k = p.get_int("feature_neighbors");
    const double color_weight = p.get_float("color_weight");
    AttributeSet set{{AttributeKind::PointId},
                     feature_degree_key(k, color_weight),
                     {AttributeKind::LocalResolution, kResolutionNeighbors}};
    if (p.get_enum_name("directional") != "none")
      set.insert(feature_line_key(p.get_int("line_neighbors"), k, p.get_float("feature_threshold"), color_weight));
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    set.insert({AttributeKind::Normal, k});  // the visibility discs' planes (and the light)
    if (p.get_bool("opacity_draws")) set.insert({AttributeKind::SplatOpacity});
    if (p.get_enum_name("coloring") == "point" || p.get_float("dither_tone") > 0.0 || p.get_float("tone") > 0.0) {
      const AttributeSet colors = color_attributes(ColorSource(p.get_enum("color_source")));
      set.insert(colors.begin(), colors.end());
    }
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override {
    // With a tone, dithering and non-directional marks grow up to 3x, and a
    // line tone widens feature marks up to 1 + it (feature_strokes_kernels.glsl).
    const double grow = p.get_float("tone") > 0.0 ? kMaxSparseGrowth : 1.0;
    const double wide = grow * std::max(1.0 + p.get_float("line_tone"), 1.0);
    const double longest = std::max({p.get_float("directional_length"), grow * p.get_float("other_length"),
                                     wide * p.get_float("sprite_size"), wide * p.get_float("stroke_width"),
                                     wide * p.get_float("line_width")});
    // A chain's link reaches from its point up to twice directional_length
    // (feature_strokes_kernels.glsl), plus half its width along and across
    // (a width at most twice the stroke's, with a line tone, and at least
    // 1.5 px; a line's quad half a pixel larger).
    const double link = chains_draw(p) ? 2.0 * p.get_float("directional_length") +
                                             2.0 * std::max({p.get_float("stroke_width"), p.get_float("line_width"), 1.5}) + 1.0
                                       : 0.0;
    MarkExtent e;
    // The farthest a point draws: its stroke or link, or its visibility disc
    // (a separate pass; a stroke is tested against the depth of the pixels
    // it covers, which the discs reaching those pixels set).
    e.pixels = float(std::max({0.5 * longest * 1.5, link, 0.5 * double(kMaxDiscPixels)}) + 2.0);
    return e;
  }

  void draw(const MarkContext& ctx, const ParamValues& p) const override;

  // Every primitive and disc is placed and textured from its frame pixel
  // (render/exact_raster.h) and every choice is per point or per cloud: a
  // tile is the bytes of the frame. No pass reads neighbouring pixels, so
  // the extent is the whole reach.
  bool draws_tiles(const ParamValues&) const override { return true; }

  // Chained points draw their links: chain_lines on where it applies (the
  // directional class draws lines or strokes; its schema condition).
  static bool chains_draw(const ParamValues& p) {
    return p.get_bool("chain_lines") && applies(*p.schema().find("chain_lines"), p);
  }

  // auto (render/backend.h): the native passes on a software GL, GL on a GPU.
  static bool native(const ParamValues& p) { return chosen_backend(p) == Backend::Native; }

 private:
  FeatureStrokeSettings resolve(const MarkContext& ctx, const ParamValues& p) const;
  mutable FeatureLineHostCache lines_;
};


int primitive_of(const std::string& name) {
  return name == "point_sprite" ? 1 : name == "line_segment" ? 2 : name == "textured_stroke" ? 3 : 0;
}

FeatureStrokeSettings FeatureStrokes::resolve(const MarkContext& ctx, const ParamValues& p) const {
  const Camera& cam = *ctx.camera;
  const glm::ivec2 size = frame_size(ctx.targets);  // the projection's
  FeatureStrokeSettings s;
  feature_strokes::FeatureStrokesSettings& u = s.u;
  u.projection = glm::mat4(cam.projection);
  u.constant_color = p.get_color("stroke_color");
  u.size_x = size.x;
  u.size_y = size.y;
  u.ortho = cam.orthographic ? 1 : 0;
  u.near_plane = float(cam.clip_start);
  u.far_plane = float(cam.clip_end);
  u.threshold = float(p.get_float("feature_threshold"));
  u.line_error = float(p.get_float("line_error"));
  u.use_lines = p.get_enum_name("directional") != "none" ? 1 : 0;
  u.dither = float(p.get_float("dither"));
  u.dither_tone = float(p.get_float("dither_tone"));
  u.prim_directional = primitive_of(p.get_enum_name("directional"));
  u.prim_other = primitive_of(p.get_enum_name("non_directional"));
  u.prim_dither = primitive_of(p.get_enum_name("dithering"));
  u.directional_length = float(p.get_float("directional_length"));
  u.other_length = float(p.get_float("other_length"));
  u.sprite_size = float(p.get_float("sprite_size"));
  u.stroke_width = float(p.get_float("stroke_width"));
  u.line_width = float(p.get_float("line_width"));
  u.point_coloring = p.get_enum_name("coloring") == "point" ? 1 : 0;
  u.light_dir = glm::vec4(view_light_direction(p, *ctx.camera), 0.0f);
  u.shading_strength = float(p.get_float("shading_strength"));
  u.opacity = float(p.get_float("opacity"));
  u.seed = uint32_t(p.get_int("seed"));
  u.tone = float(p.get_float("tone"));
  u.line_tone = float(p.get_float("line_tone"));
  u.chain_lines = chains_draw(p) ? 1 : 0;
  u.px_per_unit = float(cam.pixels_per_unit(1.0, size.y));
  // One dithering or non-directional mark's area on screen: a sprite's disc, a line's or a stroke's rectangle.
  const double other_length = p.get_float("other_length");
  auto mark_area = [&](int prim) {
    return float(prim == 1 ? 0.25 * M_PI * u.sprite_size * u.sprite_size
                 : prim == 3 ? other_length * u.stroke_width
                             : other_length * u.line_width);
  };
  u.dither_area = mark_area(u.prim_dither);
  u.other_area = mark_area(u.prim_other);
  const double angle = glm::radians(p.get_float("screen_angle"));
  u.screen_dir_x = float(std::cos(angle));
  u.screen_dir_y = float(std::sin(angle));
  u.stroke_texture = p.get_enum("stroke_texture");
  s.feature_k = p.get_int("feature_neighbors");
  s.params = &p;
  s.lit = p.get_enum_name("shading") != "none";
  s.opacity_draws = p.get_bool("opacity_draws");
  s.degree_key = feature_degree_key(s.feature_k, p.get_float("color_weight"));
  s.line_key = feature_line_key(p.get_int("line_neighbors"), s.feature_k, p.get_float("feature_threshold"),
                                p.get_float("color_weight"));
  s.color_source = ColorSource(p.get_enum("color_source"));
  s.paper = p.get_color("paper_color");
  s.disc_scale = float(p.get_float("disc_scale"));
  s.depth_offset = float(p.get_float("depth_offset"));
  // The image is read (and needed) only while some class draws textured strokes.
  if (p.get_enum_name("stroke_texture") == "image" && applies(*p.schema().find("stroke_texture"), p)) {
    const std::string& path = p.get_path("texture_image");
    if (path.empty()) throw ParameterError("feature_strokes: stroke_texture 'image' needs a texture_image");
    s.texture_image = &ctx.images->get(path, "stroke", ImageTextures::Sampling::Clamped, [](Image i) { return i; });
  }
  s.queue = draws_queue(ctx, p);
  for (const VisibleChunk& v : ctx.chunks) {
    s.drawn.push_back(queue_count(v, p));
    s.visited.push_back(u.chain_lines != 0 ? uint32_t(v.chunk->count) : s.drawn.back());
    s.inv_median_r.push_back(1.0f / median_spacing(v, kResolutionNeighbors, 1.0f));
    s.max_r.push_back(2.0f * sparse_spacing(v, kResolutionNeighbors, std::numeric_limits<float>::infinity()));
  }
  return s;
}

void FeatureStrokes::draw(const MarkContext& ctx, const ParamValues& p) const {
  const FeatureStrokeSettings s = resolve(ctx, p);
  if (native(p)) {
    draw_feature_strokes_native(ctx, s, lines_);
    return;
  }
  const Camera& cam = *ctx.camera;
  const glm::ivec2 size = frame_size(ctx.targets);  // the projection's
  const float px_per_unit = float(cam.pixels_per_unit(1.0, size.y));
  const int k = s.feature_k;
  const Rect& clip = ctx.clip;

  // Tiles: every vertex at its exact frame position (render/exact_raster.h),
  // through a viewport wide enough that nothing reaching the images is clipped.
  const ExactRaster raster = exact_raster(ctx.targets, extent(p).pixels);

  // 1. Visibility splatting: every point as an opaque disc into depth.
  {
    const gl::Program& d = ctx.shaders->graphics("feature_strokes_depth.vert", "feature_strokes_depth.frag");
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.fbo);
    const MarkRasterState state(ctx.targets, clip);
    raster.apply();
    const float zero = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &zero);  // reversed Z
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glEnable(GL_PROGRAM_POINT_SIZE);
    d.use();
    glUniformMatrix4fv(d.location("u_projection"), 1, GL_FALSE, glm::value_ptr(glm::mat4(cam.projection)));
    glUniform2i(d.location("u_size"), size.x, size.y);
    glUniform1f(d.location("u_near"), float(cam.clip_start));
    glUniform1f(d.location("u_far"), float(cam.clip_end));
    glUniform1i(d.location("u_ortho"), cam.orthographic ? 1 : 0);
    glUniform1f(d.location("u_px_per_unit"), px_per_unit);
    glUniform1f(d.location("u_disc_scale"), s.disc_scale);
    glUniform1f(d.location("u_offset"), s.depth_offset);
    glUniform1f(d.location("u_max_size"), kMaxDiscPixels);
    raster.set_uniforms(d);
    for (size_t c = 0; c < ctx.chunks.size(); ++c) {
      const VisibleChunk& v = ctx.chunks[c];
      const gl::Buffer* normals = v.gpu->find({AttributeKind::Normal, k});
      glUniform1f(d.location("u_max_r"), s.max_r[c]);
      bind_chunk(d, v, ColorSource::Constant,
                 {{2, normals}, {9, v.gpu->find({AttributeKind::LocalResolution, kResolutionNeighbors})}});
      glUniform1i(d.location("u_disc_normals"), normals ? 1 : 0);
      glBindVertexArray(v.gpu->vao.id());
      glDrawArrays(GL_POINTS, GLint(v.chunk->first), GLsizei(v.chunk->count));
    }
    glBindVertexArray(0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    gl::check_gl("feature strokes visibility pass");
  }

  // 2. Primitives: per batch, a compute pass classifies the queue's first
  // points and compacts the drawn ones; 6 vertices per record expand them.
  const InkLayer ink(ctx, "feature strokes");

  auto slots_of = [&](size_t c) { return (s.visited[c] + 127u) / 128u * 128u; };
  uint32_t largest = 0;
  for (size_t c = 0; c < ctx.chunks.size(); ++c) largest = std::max(largest, slots_of(c));
  const uint32_t capacity = std::max(kBatchPoints, largest);
  const gl::Buffer& records = ctx.targets.scratch_buffer(size_t(capacity) * sizeof(Record), 0);
  const gl::Buffer& commands = ctx.targets.scratch_buffer(size_t(capacity / 128u) * sizeof(DrawCommand), 1);
  const uint32_t zero3[3] = {0, 0, 0};
  const gl::Buffer counters = gl::make_buffer(sizeof(zero3), zero3, GL_DYNAMIC_STORAGE_BIT);

  const gl::Program& select = ctx.shaders->compute("feature_strokes_select.comp");
  select.use();
  gl::check_uniform_block(select, "FeatureStrokesSettings", sizeof(s.u), 0);
  const gl::Buffer settings = gl::make_buffer(sizeof(s.u), &s.u);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, settings.id());
  glUniform4fv(select.location("u_constant_color"), 1, glm::value_ptr(s.u.constant_color));
  glUniform1i(select.location("u_queue"), s.queue ? 1 : 0);

  const gl::Program& expand = ctx.shaders->graphics("feature_strokes.vert", "feature_strokes.frag");
  expand.use();
  gl::check_uniform_block(expand, "FeatureStrokesSettings", sizeof(s.u), 0);
  glUniform1i(expand.location("u_texture_image"), 0);
  glBindTextureUnit(0, s.texture_image ? s.texture_image->id() : ink.accum.id());
  raster.set_uniforms(expand);

  for (const RecordBatch& batch : record_batches(ctx.chunks.size(), capacity, slots_of)) {
    if (batch.begin > 0) glFinish();  // the previous batch's draw has read the records
    select.use();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, records.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, counters.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, commands.id());
    for (size_t c = batch.begin; c < batch.end; ++c) {
      const VisibleChunk& v = ctx.chunks[c];
      const GpuCloud& g = *v.gpu;
      const gl::Buffer* lines = s.u.use_lines ? g.find(s.line_key) : nullptr;
      const ColorSource resolved = resolve_color_source(s.color_source, g);
      const bool lit = lit_by_shading(p, resolved) && g.find({AttributeKind::Normal, k});
      bind_chunk(select, v, s.color_source,
                 {{2, lit ? g.find({AttributeKind::Normal, k}) : nullptr},
                  {3, g.find(s.degree_key)}, {4, lines},
                  {5, s.queue ? g.find({AttributeKind::QueueOrder}) : nullptr}, {6, g.find({AttributeKind::PointId})},
                  {9, g.find({AttributeKind::LocalResolution, kResolutionNeighbors})},
                  {11, s.opacity_draws ? g.find({AttributeKind::SplatOpacity}) : nullptr}});
      glUniform1i(select.location("u_has_lines"), lines ? 1 : 0);
      glUniform1i(select.location("u_has_opacity"), s.opacity_draws ? 1 : 0);
      glUniform1i(select.location("u_has_color"), resolved != ColorSource::Constant ? 1 : 0);
      glUniform1i(select.location("u_lit"), lit ? 1 : 0);
      glUniform1f(select.location("u_inv_median_r"), s.inv_median_r[c]);
      glUniform1f(select.location("u_max_r"), s.max_r[c]);
      glUniform1ui(select.location("u_drawn"), s.drawn[c]);
      glUniform1ui(select.location("u_visited"), s.visited[c]);
      glUniform1ui(select.location("u_out_base"), batch.offsets[c - batch.begin]);
      glUniform1ui(select.location("u_command_base"), batch.offsets[c - batch.begin] / 128u);
      glDispatchCompute(slots_of(c) / 128u, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);

    ink.begin(true, raster);
    expand.use();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, records.id());
    draw_record_batch(commands, batch);
    ink.end();
    gl::check_gl("feature strokes");

    if (ctx.capture) {
      for (const Record& rec : drawn_records<Record>(records, commands, batch, 6))
        ctx.capture->push_back(feature_strokes::captured(rec, cam.orthographic, px_per_unit));
    }
  }

  // 3. Resolve (the ink layer's): ink over paper, the surface's depth.
  ink.resolve(s.paper, true);

  uint32_t counts[3] = {0, 0, 0};
  glGetNamedBufferSubData(counters.id(), 0, sizeof(counts), counts);
  if (ctx.stats) {
    (*ctx.stats)["strokes_drawn"] += double(counts[0]) + double(counts[1]) + double(counts[2]);
    (*ctx.stats)["strokes_directional"] += double(counts[0]);
    (*ctx.stats)["strokes_non_directional"] += double(counts[1]);
    (*ctx.stats)["strokes_dithering"] += double(counts[2]);
    double queued = 0.0;
    for (uint32_t n : s.drawn) queued += double(n);
    (*ctx.stats)["queue_points"] += queued;
  }
}

const std::vector<std::string> kPrimitives = {"none", "point_sprite", "line_segment", "textured_stroke"};
// The parameters choosing each class's primitive.
const std::vector<std::string> kClasses = {"directional", "non_directional", "dithering"};
const std::vector<std::string> kUndirected = {"non_directional", "dithering"};

// A setting of some primitives applies while any of `classes` draws one.
std::vector<ParamSpec::Condition> drawn_as(const std::vector<std::string>& primitives,
                                           const std::vector<std::string>& classes) {
  std::vector<ParamSpec::Condition> conditions;
  for (const std::string& c : classes) conditions.push_back({c, primitives});
  return conditions;
}

const MarkRegistration registration{{
    with_surface_light(Schema{"feature_strokes",
           "Feature strokes",
           "Feature points (high feature degree) and dithering points drawn as point sprites, line segments or "
           "textured strokes along their fitted 3D directions, behind a visibility-splatting depth pass (Xu et al., "
           "stylized rendering of 3D scanned real world environments).",
           {
               float_param("feature_threshold", 0.35, 0.0, 1.0, "",
                           "tau: points whose feature degree is above it are feature points"),
               int_param("feature_neighbors", 8, 4, 64, "",
                         "Neighbours of the feature degree (fewer: thinner feature bands along edges)"),
               float_param("color_weight", 0.5, 0.0, 1.0, "",
                           "Weight w of the colour (or intensity) edges in the feature degree: (1 - w) x shape + "
                           "w x colour (seed 001 section 5.2; 0: shape alone, 1: colour alone; in steps of 0.05; "
                           "a scan without colours or intensity has its shape only)"),
               int_param("line_neighbors", 48, 4, 99, "",
                         "Nearest feature points the stroke direction is fitted to (eq. 2; more: straighter "
                         "directions along wide feature bands)"),
               enum_param("directional", kPrimitives, 3,
                          "Primitive of directional feature points (line fit error below line_error), along the "
                          "projected fitted direction; none: not drawn (and no line fit computed: every feature "
                          "point is non-directional)"),
               float_param("line_error", 0.2, 0.0, 0.67, "",
                           "Line fit error (eq. 2, (l0 + l1) / sum, 0 = a perfect line) below which a feature point "
                           "is directional"),
               only_when_any(added_later(bool_param("chain_lines", true,
                                                    "Directional feature points that lie along one line, linked "
                                                    "into a chain through the scan's gaps, draw it as one line "
                                                    "through them, pointed at its free ends, instead of a stroke "
                                                    "each along its own fit (the paper's; off in files saved "
                                                    "before): edges read as lines, not ticks"),
                                         {0.0}),
                             drawn_as({"line_segment", "textured_stroke"}, {"directional"})),
               enum_param("non_directional", kPrimitives, 2,
                          "Primitive of the other feature points, along the constant screen direction"),
               enum_param("dithering", kPrimitives, 1,
                          "Primitive of the dithering points (non-feature points kept for tone), along the constant "
                          "screen direction"),
               added_later(float_param("tone", 1.0, 0.0, 4.0, "",
                                       "Ink of the dithering: its marks cover this share of the surface on screen "
                                       "where it is darkest (x 1 - its shade or colour's luminance) at any scan "
                                       "density, distance and output size (overlaps cover 1 - exp(-that)); where "
                                       "non-directional feature marks are too sparse for this share (a rough "
                                       "surface, all feature points), they grow too (line_tone lights them); 0: "
                                       "the paper's range-aware odds (dither, dither_tone)"),
                           {0.0}),
               only_when(added_later(float_param("line_tone", 0.0, 0.0, 1.0, "",
                                                 "How much the light thins feature strokes, lines and sprites: "
                                                 "their width times mix(1, 2 x (1 - their shade), this), from "
                                                 "a fifth in full light to 1 + this in the dark (shading on)"),
                                     {0.0}),
                         "shading", {"diffuse", "auto"}),
               only_when(float_param("dither", 0.15, 0.0, 1.0, "",
                                     "Share of non-feature points kept as dithering points at the cloud's median "
                                     "spacing; more where the scan is sparser (uniform in 3D)"),
                         "tone", {"zero"}),
               only_when(float_param("dither_tone", 0.5, 0.0, 1.0, "",
                                     "How much darker point colours raise the dithering odds (0: colour unused)"),
                         "tone", {"zero"}),
               only_when_any(float_param("directional_length", 14.0, 1.0, 128.0, "px",
                                         "Length of directional strokes and lines"),
                             drawn_as({"line_segment", "textured_stroke"}, {"directional"})),
               only_when_any(float_param("other_length", 6.0, 1.0, 128.0, "px",
                                         "Length of non-directional and dithering strokes and lines"),
                             drawn_as({"line_segment", "textured_stroke"}, kUndirected)),
               only_when_any(float_param("stroke_width", 4.0, 0.5, 32.0, "px", "Width of textured strokes"),
                             drawn_as({"textured_stroke"}, kClasses)),
               only_when_any(float_param("line_width", 1.2, 0.5, 8.0, "px", "Width of line segments"),
                             drawn_as({"line_segment"}, kClasses)),
               only_when_any(float_param("sprite_size", 3.0, 0.5, 32.0, "px",
                                         "Diameter of point sprites (Gaussian kernel)"),
                             drawn_as({"point_sprite"}, kClasses)),
               only_when_any(float_param("screen_angle", 45.0, -180.0, 180.0, "deg",
                                         "The constant screen direction of non-directional and dithering "
                                         "primitives (0: to the right, 90: up)"),
                             drawn_as({"line_segment", "textured_stroke"}, kUndirected)),
               only_when_any(enum_param("stroke_texture", {"taper", "brush", "dry", "image"}, 0,
                                        "Alpha texture of textured strokes (seed 001 Fig. 4): tapered, bristle brush, "
                                        "dry brush, or an image (x along the stroke, y across; its alpha times its "
                                        "darkness)"),
                             drawn_as({"textured_stroke"}, kClasses)),
               only_when(image_param("texture_image", "Stroke alpha texture (x along the stroke, y across)"),
                         "stroke_texture", {"image"}),
               enum_param("coloring", {"constant", "point"}, 0, "constant: the stroke colour; point: the point's colour"),
               color_param("stroke_color", {0.08, 0.08, 0.1, 1.0}, "Stroke colour (display sRGB)"),
               color_source_param(),
               float_param("opacity", 0.9, 0.0, 1.0, "", "Opacity of every primitive"),
               paper_color_param({0.97, 0.96, 0.92, 1.0}, "strokes"),
               float_param("disc_scale", 1.5, 0.5, 4.0, "",
                           "Visibility pass: disc diameter in local resolutions (mean spacing to 8 neighbours; "
                           "large enough for a hole-free surface)"),
               float_param("depth_offset", 1.5, 0.0, 10.0, "",
                           "Visibility pass: discs pushed away along the view ray by this many local resolutions, so "
                           "strokes on the visible surface pass the depth test"),
               density_mode_param(),
               queue_level_param(0.05),
               int_param("seed", 0, 0, 65535, "", "Varies the dithering choice (still fixed per point)"),
               bool_param("opacity_draws", false,
                          "A Gaussian-splat capture's opacity is each splat's chance of a stroke (the same splats "
                          "as the points mark draws; its faint haze gets few; plain points: unchanged)"),
               rasterizer_param("gl: the GL passes (discs into depth, instanced quads, blending); native: the same "
                                "passes on the CPU's threads (the same images but for the kernels' last bits and rare "
                                "coverage ties)"),
           }},
                       "the dithering's tone by the points' normals", 0.8),
    [] { return std::make_unique<FeatureStrokes>(); }}};

}  // namespace
}  // namespace pointnpr
