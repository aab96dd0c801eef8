// Stroke-based splatting (seed 004, impressionist brush strokes on
// surface-aligned splats): every point becomes a square splat of radius
// r + eps (the mean distance to its k nearest neighbours and its deviation,
// or a user eps: denser regions get smaller brushes), lying in its tangent
// plane, textured by a brush that is a mixture of Gaussians (eq. 1).
//
//  - Tangent frame per point in the vertex shader from the normal alone:
//    the Householder formula (section 3.3.1), or, for the comparison of the
//    seed's Fig. 3, Eberly's cross products, a square-plate stand-in, or
//    the covariance matrix (the neighbourhood's major axis, per point).
//  - Brush: N Gaussians (1..9) on a 3 x 3 grid, dev apart, amplitude A,
//    shape exponent lambda, sigma x / y, theta per column: the brush angle
//    plus seeded noise (point id), each column within a bound of the
//    previous. Up to two layers (the second smaller, turned, tinted).
//  - Depth pass: every brush (alpha from kSurfaceCut) into depth, nearest
//    wins. Splats then blend order-independently within `depth_tolerance`
//    radii of that surface (at least brush_noise_offset): weighted average
//    colour, coverage = 1 - product of transmittances (sums and products
//    in a fixed primitive order: the same bytes in every process).
//  - Blending (a): two-pass Gaussian blur of the colour with depth
//    occlusion (neighbours at other depths do not mix), coverage unchanged.
//  - Blending (b): an A-buffer of the splats near the surface, sorted and
//    blended front to back per pixel (a_buffer.cpp), within a memory
//    budget; a frame over it warns and is blended by (a). The seed's
//    incremental bubble sort across viewport frames is not done: every
//    frame sorts completely.
//  - Tiles (brush_splats_tiled.*): the same passes with every fragment
//    computed from its frame pixel, so a frame drawn in tiles is the bytes
//    of the frame drawn whole by this exact path. Frames drawn whole use
//    the faster interpolating passes (about 3x faster on a software GL)
//    unless tile_invariant asks for the exact path for every frame.
//  - rasterizer native (auto on a software GL, for blur and none): the
//    exact path's rules on the CPU's threads (native.cpp).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "geometry/analysis.h"
#include "marks/brush_splats/brush_splats.h"
#include "marks/brush_splats/gl_passes.h"
#include "marks/points/points.h"
#include "render/backend.h"
#include "render/exact_raster.h"
#include "render/ink_layer.h"
#include "scene/camera.h"

namespace pointnpr {
namespace {

// GPU record of one captured splat (std430, 64 bytes; brush_capture.comp).
struct SplatRecord {
  glm::vec4 center_size;
  glm::vec4 tangent;
  glm::vec4 normal_id;
  glm::vec4 color;
};
static_assert(sizeof(SplatRecord) == 64);

// Largest splat radius on screen the parameter allows (bounds the mark's
// extent and fill rate).
constexpr float kMaxRadiusPixels = 64.0f;
constexpr float kCut = kBrushCut;

// Normals: the cloud's own, else k-neighbour PCA or least squares within 3r.
AttributeKey normal_key(const ParamValues& p) {
  return {p.get_enum_name("normals") == "radius_3r" ? AttributeKind::RadiusNormal : AttributeKind::Normal,
          p.get_int("normal_neighbors")};
}

class BrushSplats final : public Mark {
 public:
  AttributeSet attributes(const ParamValues& p) const override {
    AttributeSet set = color_attributes(ColorSource(p.get_enum("color_source")));
    set.insert({AttributeKind::PointId});
    set.insert(normal_key(p));
    if (p.get_enum_name("size_mode") == "resolution") {
      const int k = p.get_int("resolution_neighbors");
      set.insert({AttributeKind::LocalResolution, k});
      if (p.get_enum_name("epsilon_mode") == "deviation") set.insert({AttributeKind::ResolutionDeviation, k});
    }
    if (p.get_enum_name("size_mode") == "splat")
      set.insert({AttributeKind::SplatRadius, p.get_int("resolution_neighbors")});
    if (p.get_bool("opacity_weight")) set.insert({AttributeKind::SplatOpacity});
    if (p.get_enum_name("tangent_frame") == "covariance")
      set.insert({AttributeKind::PrincipalAxis, p.get_int("normal_neighbors")});
    if (p.get_bool("clusters")) set.insert({AttributeKind::ClusterShape, p.get_int("cluster_neighbors")});
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override {
    // max_radius bounds how far a splat's quad reaches (its corner).
    return {0.0, float(p.get_float("max_radius")) + 2.0f};
  }

  // In tiles (and with tile_invariant) fragments are computed from their
  // frame pixel and placed on a grid that the tile's origin shifts exactly
  // (brush_splats_tiled.vert): a tile is the bytes of the frame drawn whole
  // by that path. The blur reads its radius around a pixel (the A-buffer's
  // fallback too).
  bool draws_tiles(const ParamValues&) const override { return true; }
  int screen_reach(const ParamValues& p) const override {
    // The rims' marches, then the blur's taps.
    const int rims = int(std::ceil(p.get_float("max_radius")));
    return rims + (p.get_enum_name("blending") == "none" ? 0 : p.get_int("blur_radius"));
  }

  void draw(const MarkContext& ctx, const ParamValues& p) const override;
  // False where an A-buffer over its budget handed the frame to the native passes.
  bool draw_gl(const MarkContext& ctx, const ParamValues& p) const;
  void capture_splats(const MarkContext& ctx, const ParamValues& p) const;

  // auto (render/backend.h): the native passes on a software GL, for blur
  // and none; the A-buffer's lists are GL's on every device.
  static bool native(const ParamValues& p) {
    return p.get_enum_name("blending") != "a_buffer" && native_blur(p);
  }
  // Whether blur blends natively: also an A-buffer's fallback over its budget.
  static bool native_blur(const ParamValues& p) { return chosen_backend(p) == Backend::Native; }
};

// Whether the splats take the exact path: every tile of a frame drawn in
// tiles, and every frame with tile_invariant.
bool exact_path(const MarkTargets& t, const ParamValues& p) {
  return p.get_bool("tile_invariant") || t.size != frame_size(t) || t.origin != glm::ivec2(0);
}

// The exact raster of the splats (render/exact_raster.h) when they take
// the exact path; a margin of twice the mark's extent, so no splat reaching
// the images is clipped (clipping would move corners off the grid). Else
// none: the frame's viewport (MarkRasterState).
std::optional<ExactRaster> raster_viewport(const MarkContext& ctx, const ParamValues& p, const BrushSplats& mark) {
  if (!exact_path(ctx.targets, p)) return std::nullopt;
  return exact_raster(ctx.targets, float(2 * int(std::ceil(mark.extent(p).pixels)) + 1));
}

}  // namespace

namespace brush_gl {

void set_raster_viewport(const gl::Program& g, const std::optional<ExactRaster>& raster) {
  if (!raster) return;
  raster->apply();
  raster->set_uniforms(g);
}

void set_splat_uniforms(const gl::Program& g, const MarkContext& ctx, const ParamValues& p) {
  const Camera& cam = *ctx.camera;
  glUniformMatrix4fv(g.location("u_projection"), 1, GL_FALSE, glm::value_ptr(glm::mat4(cam.projection)));
  glUniform1i(g.location("u_ortho"), cam.orthographic ? 1 : 0);
  glUniform1f(g.location("u_near"), float(cam.clip_start));
  glUniform1f(g.location("u_far"), float(cam.clip_end));
  const glm::ivec2 frame = frame_size(ctx.targets);
  glUniform1f(g.location("u_px_per_unit"), float(cam.pixels_per_unit(1.0, frame.y)));
  // Fragments by their frame pixel: the tile's origin, and the pixel's ray
  // (its point on the near plane: the projection's inverse after the
  // pixel's NDC, composed in double).
  glUniform2f(g.location("u_frame_size"), float(frame.x), float(frame.y));
  glUniform2i(g.location("u_origin"), ctx.targets.origin.x, ctx.targets.origin.y);
  glm::dmat4 ndc_from_pixel(0.0);
  ndc_from_pixel[0][0] = 2.0 / double(frame.x);
  ndc_from_pixel[1][1] = 2.0 / double(frame.y);
  ndc_from_pixel[3] = glm::dvec4(-1.0, -1.0, -1.0, 1.0);
  const glm::mat4 view_from_pixel(glm::inverse(cam.projection) * ndc_from_pixel);
  glUniformMatrix4fv(g.location("u_view_from_pixel"), 1, GL_FALSE, glm::value_ptr(view_from_pixel));
  const bool resolution = p.get_enum_name("size_mode") == "resolution";
  const bool world = p.get_enum_name("size_mode") == "world";
  glUniform1i(g.location("u_size_mode"), resolution ? 0 : world ? 1 : 2);
  glUniform1i(g.location("u_opacity_weight"), p.get_bool("opacity_weight") ? 1 : 0);
  glUniform1i(g.location("u_eps_mode"), resolution && p.get_enum_name("epsilon_mode") == "user" ? 1 : 0);
  glUniform1f(g.location("u_epsilon"), resolution ? float(p.get_float("epsilon")) : 0.0f);
  glUniform1f(g.location("u_size_scale"), float(p.get_float("size_scale")));
  glUniform1f(g.location("u_world_radius"), world ? float(p.get_float("world_radius")) : 0.0f);
  glUniform1f(g.location("u_max_radius_px"), float(p.get_float("max_radius")));
  const BrushSupport support = brush_support(p);
  glUniform2f(g.location("u_support"), support.along, support.across2);
  glUniform1i(g.location("u_frame"), p.get_enum("tangent_frame"));
  glUniform1f(g.location("u_angle"), float(glm::radians(p.get_float("brush_angle"))));
  glUniform1f(g.location("u_angle_jitter"), float(glm::radians(p.get_float("angle_jitter"))));
  glUniform1ui(g.location("u_seed"), uint32_t(p.get_int("seed")));
  glUniform4fv(g.location("u_constant_color"), 1, glm::value_ptr(p.get_color("color")));
  glUniform1f(g.location("u_shading_strength"), float(p.get_float("shading_strength")));
  glUniform3fv(g.location("u_light_dir"), 1, glm::value_ptr(view_light_direction(p, cam)));
  // Brush (fragment stage).
  glUniform1i(g.location("u_gaussians"), p.get_int("gaussians"));
  glUniform1f(g.location("u_amplitude"), float(p.get_float("amplitude")));
  glUniform1f(g.location("u_dev"), float(p.get_float("dev")));
  glUniform1f(g.location("u_lambda"), float(p.get_float("lambda")));
  glUniform1f(g.location("u_sigma_x"), float(p.get_float("sigma_x")));
  glUniform1f(g.location("u_sigma_y"), float(p.get_float("sigma_y")));
  glUniform1i(g.location("u_layers"), p.get_enum("layers") + 1);
  glUniform1f(g.location("u_layer_scale"), float(p.get_float("layer_scale")));
  glUniform1f(g.location("u_layer_angle"), float(glm::radians(p.get_float("layer_angle"))));
  glUniform1f(g.location("u_layer_tint"), float(p.get_float("layer_tint")));
  const bool clusters = p.get_bool("clusters");
  glUniform1i(g.location("u_clusters"), clusters ? 1 : 0);
  glUniform1f(g.location("u_small_cluster"), clusters ? float(p.get_int("small_cluster")) : 0.0f);
  glUniform1f(g.location("u_elongation_gain"), float(p.get_float("elongation_stretch")));
  glUniform1f(g.location("u_max_stretch"), float(p.get_float("max_stretch")));
  glUniform1f(g.location("u_cut"), kCut);
  glUniform1f(g.location("u_surface_cut"), kSurfaceCut);
  glUniform1f(g.location("u_reach"), float(brush_reach(p)));
}

void bind_splat_chunk(const gl::Program& g, const VisibleChunk& v, const ParamValues& p) {
  const GpuCloud& c = *v.gpu;
  glUniform1f(g.location("u_noise_offset"), brush_noise_offset(*chunk_cloud(v, "brush_splats"), p));
  const int k = p.get_int("resolution_neighbors");
  bind_chunk(g, v, ColorSource(p.get_enum("color_source")),
             {{2, c.find(normal_key(p))},
              {3, c.find({AttributeKind::LocalResolution, k})},
              {4, c.find({AttributeKind::ResolutionDeviation, k})},
              {5, c.find({AttributeKind::ClusterShape, p.get_int("cluster_neighbors")})},
              {6, c.find({AttributeKind::PointId})},
              {13, c.find({AttributeKind::PrincipalAxis, p.get_int("normal_neighbors")})},
              {14, c.find({AttributeKind::QueueOrder})},
              {15, c.find({AttributeKind::SplatRadius, k})},
              {16, c.find({AttributeKind::SplatOpacity})}});
  const bool queued = draws_queue(v, p);
  if (queued && !c.find({AttributeKind::QueueOrder})) throw GLError("brush_splats: the queue order was not uploaded");
  glUniform1i(g.location("u_queue"), queued ? 1 : 0);
  glUniform1ui(g.location("u_count"), queue_count(v, p));
  glUniform1i(g.location("u_shading"),
              lit_by_shading(p, resolve_color_source(ColorSource(p.get_enum("color_source")), c)) ? 1 : 0);
}

// The passes' framebuffer: colour attachments (none for the A-buffer's
// passes, which write buffers) and the GL depth.
gl::Framebuffer make_fbo(std::initializer_list<const gl::Texture*> colors, const MarkTargets& targets) {
  return gl::make_framebuffer(colors, targets.gl_depth, "brush_splats");
}

// The splat shaders of one pass; the second layer's code only where the
// style can ask for it (layers two, or clusters that make small ones two).
const gl::Program& splat_program(const MarkContext& ctx, const ParamValues& p, const char* pass) {
  const bool two_layers = p.get_enum_name("layers") == "two" || p.get_bool("clusters");
  const bool tiled = exact_path(ctx.targets, p);
  const char* vert = tiled ? "brush_splats_tiled.vert" : "brush_splats.vert";
  const char* frag = tiled ? "brush_splats_tiled.frag" : "brush_splats.frag";
  if (two_layers) return ctx.shaders->graphics(vert, frag, {pass, "TWO_LAYERS"});
  return ctx.shaders->graphics(vert, frag, {pass});
}

void draw_all(const MarkContext& ctx, const gl::Program& g, const ParamValues& p) {
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  const gl::VertexArray empty_vao(vao);
  glBindVertexArray(vao);
  for (const VisibleChunk& v : ctx.chunks) {
    bind_splat_chunk(g, v, p);
    const uint32_t count = queue_count(v, p);
    if (count > 0) glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(count));
  }
  glBindVertexArray(0);
}

// Splats near the surface, moved toward the camera by depth_tolerance radii:
// the GL depth test against the depth pass (no depth writes); with
// tile_invariant it only culls (by a bound per splat) and the fragment
// shader decides against the depth pass's linear depth (image unit 0).
void near_surface_tests(const MarkContext& ctx, const gl::Program& g, const ParamValues& p) {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_FALSE);
  glBindImageTexture(0, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glUniform1f(g.location("u_offset_radii"), float(p.get_float("depth_tolerance")));
}

// gl_passes.h: from the segment's colour and depth into `sums`, copied back.
void draw_rims(const MarkContext& ctx, const ParamValues& p) {
  const Rect& clip = ctx.clip;
  const gl::Texture& sums = ctx.targets.scratch(GL_RGBA32F, 1);
  const RimReach rim = rim_reach(ctx, p);
  const gl::Program& g = ctx.shaders->compute("brush_rims.comp");
  g.use();
  glUniform2f(g.location("u_footprint"), rim.footprint0, rim.footprint1);
  glUniform1f(g.location("u_grazing"), kSteepestSurfaceSlope);
  glUniform1i(g.location("u_reach"), rim.reach);
  glUniform2i(g.location("u_clip_min"), clip.min.x, clip.min.y);
  glUniform2i(g.location("u_clip_max"), clip.max.x, clip.max.y);
  glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(2, sums.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(3, ctx.targets.scratch(GL_R32F, 2).id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  dispatch_rect(g, clip);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  glCopyImageSubData(sums.id(), GL_TEXTURE_2D, 0, clip.min.x, clip.min.y, 0, ctx.targets.color->id(), GL_TEXTURE_2D,
                     0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

}  // namespace brush_gl

namespace {
using namespace brush_gl;

// Blending by weighted average and the blur (a).
void draw_blended(const MarkContext& ctx, const ParamValues& p, bool blur, const std::optional<ExactRaster>& raster) {
  const Rect& clip = ctx.clip;
  const gl::Texture& accum = ctx.targets.scratch(GL_RGBA32F, 0);
  const gl::Texture& reveal = ctx.targets.scratch(GL_R32F, 0);
  const gl::Texture& splat_depth = ctx.targets.scratch(GL_R32F, 1);
  const float zero4[4] = {0, 0, 0, 0}, one = 1.0f, inf = std::numeric_limits<float>::infinity();
  glClearTexSubImage(accum.id(), 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1, GL_RGBA, GL_FLOAT, zero4);
  glClearTexSubImage(reveal.id(), 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1, GL_RED, GL_FLOAT, &one);
  glClearTexSubImage(splat_depth.id(), 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1, GL_RED, GL_FLOAT, &inf);
  const gl::Framebuffer blend_fbo = make_fbo({&accum, &reveal, &splat_depth}, ctx.targets);
  {
    const MarkRasterState state(ctx.targets, ctx.clip);
    glBindFramebuffer(GL_FRAMEBUFFER, blend_fbo.id());
    InkLayer::blend_modes();
    const gl::Program& blend = splat_program(ctx, p, "PASS_BLEND");
    blend.use();
    set_splat_uniforms(blend, ctx, p);
    set_raster_viewport(blend, raster);
    near_surface_tests(ctx, blend, p);
    draw_all(ctx, blend, p);
  }
  gl::check_gl("brush splats");
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);

  // Resolve into the segment's colour and depth.
  const gl::Program& resolve = ctx.shaders->compute("brush_resolve.comp");
  resolve.use();
  glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  glBindImageTexture(2, accum.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(3, reveal.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(4, splat_depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  dispatch_rect(resolve, clip);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

  draw_rims(ctx, p);
  const gl::Texture& sums = ctx.targets.scratch(GL_RGBA32F, 1);

  // Blur with depth occlusion.
  const int radius = p.get_int("blur_radius");
  if (!blur || radius <= 0) return;
  const float sigma = std::max(0.5f, 0.5f * float(radius));
  for (const char* pass : {"PASS_X", "PASS_Y"}) {
    const bool x = std::string(pass) == "PASS_X";
    const gl::Program& g = ctx.shaders->compute("brush_blur.comp", {pass});
    g.use();
    glUniform1f(g.location("u_sigma"), sigma);
    glUniform1i(g.location("u_radius"), radius);
    glUniform1f(g.location("u_depth_tolerance"), float(p.get_float("blur_depth_tolerance")));
    glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindImageTexture(2, sums.id(), 0, GL_FALSE, 0, x ? GL_WRITE_ONLY : GL_READ_ONLY, GL_RGBA32F);
    if (!x) glBindImageTexture(3, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    dispatch_rect(g, clip);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  }
}

void BrushSplats::draw(const MarkContext& ctx, const ParamValues& p) const {
  if (native(p)) {
    draw_brush_splats_native(ctx, p);
  } else if (draw_gl(ctx, p)) {
    uint64_t drawn = 0;
    for (const VisibleChunk& v : ctx.chunks) drawn += queue_count(v, p);
    if (ctx.stats) (*ctx.stats)["splats_drawn"] += double(drawn);
  }
  if (ctx.capture) capture_splats(ctx, p);
}

bool BrushSplats::draw_gl(const MarkContext& ctx, const ParamValues& p) const {
  // 1. Depth pass: the nearest brush surface per pixel (GL depth, reversed
  // Z, from each fragment's own depth; its linear depth in the segment's).
  const std::optional<ExactRaster> raster = raster_viewport(ctx, p, *this);
  // With the depth, the blend offset of the surface's splat (its rims'
  // test, brush_rims.glsl; 0 where no brush is the surface).
  const gl::Texture& surface_offset = ctx.targets.scratch(GL_R32F, 2);
  const float no_offset = 0.0f;
  glClearTexSubImage(surface_offset.id(), 0, ctx.clip.min.x, ctx.clip.min.y, 0, ctx.clip.size().x,
                     ctx.clip.size().y, 1, GL_RED, GL_FLOAT, &no_offset);
  const gl::Framebuffer depth_fbo = make_fbo({ctx.targets.depth, &surface_offset}, ctx.targets);
  {
    const MarkRasterState state(ctx.targets, ctx.clip);
    glBindFramebuffer(GL_FRAMEBUFFER, depth_fbo.id());
    const float zero = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &zero);  // reversed Z: 0 is the far end
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    const gl::Program& depth_pass = splat_program(ctx, p, "PASS_DEPTH");
    depth_pass.use();
    set_splat_uniforms(depth_pass, ctx, p);
    set_raster_viewport(depth_pass, raster);
    glUniform1f(depth_pass.location("u_offset_radii"), float(p.get_float("depth_tolerance")));
    draw_all(ctx, depth_pass, p);
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);

  // 2. The splats near that surface, blended.
  const std::string blending = p.get_enum_name("blending");
  if (blending == "a_buffer" && draw_a_buffer(ctx, p, raster)) {
    draw_rims(ctx, p);
    return true;
  }
  if (blending == "a_buffer" && native_blur(p)) {
    // Over its budget: blur, by the native passes where they would draw
    // blur (the whole mark again, over ctx.clip).
    draw_brush_splats_native(ctx, p);
    return false;
  }
  draw_blended(ctx, p, blending != "none", raster);
  return true;
}

// Captured splats, per chunk (chunks are bounded in size), on either path.
void BrushSplats::capture_splats(const MarkContext& ctx, const ParamValues& p) const {
  {
    const gl::Program& capture = ctx.shaders->compute("brush_capture.comp");
    capture.use();
    set_splat_uniforms(capture, ctx, p);
    for (const VisibleChunk& v : ctx.chunks) {
      const uint32_t count = queue_count(v, p);
      if (count == 0) continue;
      const gl::Buffer records = gl::make_buffer(size_t(count) * sizeof(SplatRecord), nullptr, 0);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, records.id());
      bind_splat_chunk(capture, v, p);
      glDispatchCompute((count + 127) / 128, 1, 1);
      glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
      std::vector<SplatRecord> out(count);
      glGetNamedBufferSubData(records.id(), 0, GLsizeiptr(out.size() * sizeof(SplatRecord)), out.data());
      for (const SplatRecord& r : out) {
        if (!(r.center_size.w > 0.0f)) continue;
        CapturedMark m;
        uint32_t id = 0;
        std::memcpy(&id, &r.normal_id.w, sizeof(id));
        m.point_id = id;
        m.center = glm::vec3(r.center_size);
        m.direction = glm::vec3(r.tangent);
        m.crossed = r.tangent.w > 0.5f;  // a second layer
        m.normal = glm::vec3(r.normal_id);
        m.length = r.center_size.w;
        m.color = r.color;
        ctx.capture->push_back(m);
      }
    }
  }
}

}  // namespace

float brush_noise_offset(const PointCloud& cloud, const ParamValues& p) {
  // Two samples of one surface differ by sqrt(2) sigma (RMS): three sigma
  // holds 97 % of their differences.
  constexpr float kDeviations = 3.0f;
  return kDeviations * cloud.analysis().plane_deviation(p.get_int("normal_neighbors"));
}

double brush_reach(const ParamValues& p) {
  // A N exp(-q^lambda / 2) < cut / 16 beyond q = (2 ln(16 A N / cut))^(1 / lambda): skipped Gaussians
  // change the alpha by less than a 16th of the cut.
  const double an = std::max(p.get_float("amplitude") * p.get_int("gaussians"), 1e-6);
  return std::pow(2.0 * std::log(std::max(16.0 * an / double(kBrushCut), 1.0 + 1e-6)), 1.0 / p.get_float("lambda"));
}

BrushSupport brush_support(const ParamValues& p) {
  // The centres' farthest from the middle (uv), brush_texture.glsl's grid.
  const int n = p.get_int("gaussians"), rows = (n + 2) / 3;
  const double dev = p.get_float("dev");
  double centre = 0.0;
  for (int row = 0; row < rows; ++row) {
    const int cols = std::clamp(n - row * 3, 0, 3);
    const double y = (double(row) - 0.5 * double(rows - 1)) * dev, x = 0.5 * double(cols - 1) * dev;
    centre = std::max(centre, std::sqrt(x * x + y * y));
  }
  // Beyond q^lambda = 2 ln(A N / cut) in both axes' sum no Gaussian adds a
  // cut / (A N); the sum q_x^lambda + q_y^lambda is at least
  // (|d| / sigma)^lambda for lambda <= 2 and 2 (|d| / (sqrt 2 sigma))^lambda
  // above (power means), so |d| past `spread` leaves the alpha below the cut.
  const double lambda = p.get_float("lambda");
  const double an = std::max(p.get_float("amplitude") * n, 1e-6);
  const double q = std::pow(2.0 * std::log(std::max(an / double(kBrushCut), 1.0)), 1.0 / lambda);
  const double widen = lambda > 2.0 ? std::sqrt(2.0) * std::pow(2.0, -1.0 / lambda) : 1.0;
  const double spread = std::max(p.get_float("sigma_x"), p.get_float("sigma_y")) * q * widen;
  // In radii (the quad is 2 radii wide, uv 0..1), within the quad.
  const double k = 2.0 * (centre + spread);
  return {float(std::min(k, 1.0)), float(std::clamp(k * k - 1.0, 0.0, 1.0))};
}

namespace {

// A second, smaller brush layer is painted with layers two, or on small
// clusters when brushes follow clusters.
const std::vector<ParamSpec::Condition> kSecondLayer = {{"layers", {"two"}}, {"clusters", {"true"}}};

const MarkRegistration registration{{
    with_surface_light(Schema{"brush_splats",
           "Brush splats",
           "Impressionist brush strokes on surface-aligned splats sized by the local point spacing (stroke-based "
           "splatting, seed 004): a brush of Gaussians per point, blended.",
           {
               enum_param("size_mode", {"resolution", "world", "splat"}, 0,
                          "resolution: splat radius r + eps from each point's neighbours (denser regions get "
                          "smaller brushes); world: one radius in scene units; splat: a Gaussian-splat capture's "
                          "own footprint, 2 sqrt of the product of its two largest scales (plain points: r). world "
                          "and splat as the points mark's size_mode; resolution is no one size on screen (its "
                          "pixels)"),
               only_when(int_param("resolution_neighbors", 8, 2, 64, "",
                                   "Neighbours the local resolution r (mean distance) and eps (its deviation) come from"),
                         "size_mode", {"resolution", "splat"}),
               only_when(enum_param("epsilon_mode", {"deviation", "user"}, 0,
                                    "eps: the deviation of the neighbour distances, or your own"),
                         "size_mode", {"resolution"}),
               only_when(float_param("epsilon", 0.0, 0.0, 100.0, "m", "Your eps, added to r (epsilon_mode = user)"),
                         "epsilon_mode", {"user"}),
               only_when(float_param("world_radius", 0.02, 0.00001, 100.0, "m", "Splat radius (size_mode = world)"),
                         "size_mode", {"world"}),
               float_param("size_scale", 1.5, 0.1, 8.0, "",
                           "Splat radius times this (1: r + eps; the brush's Gaussians fade before the square's edge)"),
               float_param("max_radius", 16.0, 0.5, kMaxRadiusPixels, "px",
                           "How far a brush's visible part reaches from its point on screen, stretch included "
                           "(isolated points far from their neighbours stay small)"),
               enum_param("tangent_frame", {"householder", "eberly", "square_plate", "covariance"}, 0,
                          "How the brush's axes follow from the normal: Householder formula (continuous, the seed's "
                          "choice), Eberly's cross products, a square-plate stand-in, or the neighbourhood's "
                          "covariance matrix (its major axis; the seed's Fig. 3)"),
               enum_param("normals", {"neighbors", "radius_3r"}, 0,
                          "Where a cloud has no normals: the plane of the k nearest neighbours, or the seed's "
                          "least squares within 3r (r: the mean distance to 8 neighbours)"),
               int_param("normal_neighbors", 16, 3, 64, "",
                         "Neighbours the normals (where a cloud has none) and the covariance frame are estimated "
                         "from (PCA)"),
               int_param("gaussians", 9, 1, 9, "", "Gaussians of the brush, on a 3 x 3 grid (the seed uses 6 to 9)"),
               float_param("amplitude", 1.0, 0.0, 16.0, "", "Amplitude A of every Gaussian: the brush's opacity"),
               float_param("dev", 0.38, 0.0, 0.5, "", "Spacing of the Gaussians' centres, in brush widths"),
               float_param("lambda", 2.7, 0.5, 16.0, "", "Shape exponent: 2 round Gaussians, higher squarer"),
               float_param("sigma_x", 0.142, 0.005, 1.0, "", "Decay along the brush's x axis, in brush widths"),
               float_param("sigma_y", 0.071, 0.005, 1.0, "", "Decay along its y axis, in brush widths"),
               float_param("brush_angle", 0.0, -180.0, 180.0, "deg", "Orientation theta of the Gaussians"),
               float_param("angle_jitter", 10.0, 0.0, 90.0, "deg",
                           "Seeded noise of theta: each column of Gaussians within this of the previous one"),
               enum_param("layers", {"one", "two"}, 0, "Brush layers: two paints a second, smaller layer over the first"),
               only_when_any(float_param("layer_scale", 0.6, 0.1, 1.0, "",
                                         "Size of the second layer (layers two, or small clusters)"),
                             kSecondLayer),
               only_when_any(float_param("layer_angle", 35.0, -180.0, 180.0, "deg", "Turn of the second layer"),
                             kSecondLayer),
               only_when_any(float_param("layer_tint", 0.25, -1.0, 1.0, "",
                                         "Second layer's colour toward white (> 0) or black (< 0)"),
                             kSecondLayer),
               bool_param("clusters", false,
                          "Shape brushes by colour region-growing clusters (seed 004 section 3.2.1; computed once "
                          "per cloud): small clusters get two layers, elongated ones longer brushes along their "
                          "main axis"),
               only_when(int_param("cluster_neighbors", 30, 3, 64, "", "Neighbours the region growing follows"),
                         "clusters", {"true"}),
               only_when(int_param("small_cluster", 200, 0, 1000000, "",
                                   "Clusters of fewer points get a two-layered brush"),
                         "clusters", {"true"}),
               only_when(float_param("elongation_stretch", 0.5, 0.0, 2.0, "",
                                     "Brushes longer along an elongated cluster's main axis by elongation^this "
                                     "(elongation: sqrt of the ratio of its two largest principal variances)"),
                         "clusters", {"true"}),
               only_when(float_param("max_stretch", 3.0, 1.0, 4.0, "", "Longest brush, in brush widths"),
                         "clusters", {"true"}),
               color_source_param(),
               color_param("color", {0.8, 0.8, 0.8, 1.0}, "Constant color (display sRGB)"),
               // New values last: stored enum indices keep their meaning.
               float_param("depth_tolerance", 1.0, 0.0, 10.0, "",
                           "Splats blend with the nearest surface within this many radii behind it (and always "
                           "within three standard deviations of the scan's own depth noise)"),
               enum_param("blending", {"blur", "a_buffer", "none"}, 0,
                          "blur: splats averaged, then a two-pass Gaussian blur with depth occlusion; a_buffer: per "
                          "pixel lists sorted by depth and alpha-blended front to back; none: splats averaged"),
               only_when(float_param("a_buffer_budget", 256.0, 1.0, 4096.0, "MiB",
                                     "Most memory the A-buffer's fragments may take; a frame that needs more is "
                                     "blended by blur (with a warning)"),
                         "blending", {"a_buffer"}),
               only_when(int_param("blur_radius", 2, 0, 16, "px",
                                   "Blur radius (sigma = half of it); also the A-buffer's fallback"),
                         "blending", {"blur", "a_buffer"}),
               only_when(float_param("blur_depth_tolerance", 0.02, 0.0, 1.0, "",
                                     "Neighbours mix only within this fraction of the depth"),
                         "blending", {"blur", "a_buffer"}),
               int_param("seed", 0, 0, 65535, "", "Varies the brushes' noise (still fixed per point)"),
               bool_param("opacity_weight", false,
                          "A Gaussian-splat capture's opacity weighs each brush's alpha (faint splats paint faintly, "
                          "and those under the cut not at all; plain points: 1)"),
               rasterizer_param("gl: the GL passes (for GPUs); native: the exact passes' rules on the CPU's threads "
                                "(tile-invariant, the same bytes with any thread count; the A-buffer stays on GL)"),
               bool_param("tile_invariant", false,
                          "Every frame by the exact path that frames drawn in tiles (over the memory budget) take, "
                          "so any size and budget give the same bytes (about 2.5x the time on a software GL); off, "
                          "frames drawn whole take the faster interpolating passes"),
               density_mode_param(),
               queue_level_param(0.5),
           }},
                       "each brush by its splat's plane", 0.6),
    [] { return std::make_unique<BrushSplats>(); }}};

}  // namespace
}  // namespace pointnpr
