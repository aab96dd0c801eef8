// The points mark: every point a round splat (seed 000's rasterization),
// by a compute rasterizer (after Schuetz et al. 2021: visibility by atomicMin
// on linear depth, deterministic tie break on the point key) or by
// conventional GL_POINTS (the reference and benchmark baseline). Optional
// diffuse shading by per-point normals.
#include "marks/points/points.h"

#include <cmath>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "render/backend.h"
#include "render/exact_raster.h"
#include "render/filter_chain.h"  // kGapSpacingNeighbours
#include "scene/camera.h"

namespace pointnpr {
namespace {

// Plain points' footprint in size_mode splat: the mean distance to this many neighbours.
constexpr int kSplatNeighbors = 8;

void set_splat_uniforms(const gl::Program& p, const MarkContext& ctx, const SplatSettings& s) {
  const Camera& cam = *ctx.camera;
  // The projection maps to the whole frame; the images hold [origin, origin + image size).
  const glm::ivec2 size = frame_size(ctx.targets);
  glUniformMatrix4fv(p.location("u_projection"), 1, GL_FALSE, glm::value_ptr(glm::mat4(cam.projection)));
  glUniform2i(p.location("u_size"), size.x, size.y);
  glUniform2i(p.location("u_origin"), ctx.targets.origin.x, ctx.targets.origin.y);
  glUniform1i(p.location("u_image_width"), ctx.targets.size.x);
  glUniform1f(p.location("u_near"), float(cam.clip_start));
  glUniform1f(p.location("u_far"), float(cam.clip_end));
  glUniform1i(p.location("u_ortho"), cam.orthographic ? 1 : 0);
  glUniform1i(p.location("u_size_mode"), s.world_size ? (s.splat_size ? 2 : 1) : 0);
  glUniform1i(p.location("u_opacity_draws"), s.opacity_draws ? 1 : 0);
  glUniform1f(p.location("u_point_size"), s.point_size);
  glUniform1f(p.location("u_world_size"), s.world_diameter);
  glUniform1f(p.location("u_px_per_unit"), float(cam.pixels_per_unit(1.0, size.y)));
  glUniform1f(p.location("u_max_size"), kMaxSplatPixels);
  glUniform1f(p.location("u_radius_diameters"), s.radius_diameters);
  glUniform1f(p.location("u_min_size"), s.min_pixels);
  glUniform4fv(p.location("u_constant_color"), 1, glm::value_ptr(s.constant_color));
  glUniform4i(p.location("u_clip_rect"), ctx.clip.min.x, ctx.clip.min.y, ctx.clip.max.x, ctx.clip.max.y);
  glUniform1i(p.location("u_shading"), s.shading ? 1 : 0);
  glUniform1f(p.location("u_shading_strength"), s.shading_strength);
  glUniform3fv(p.location("u_light_dir"), 1, glm::value_ptr(s.light_dir));
  glUniform1i(p.location("u_write_spacing"), ctx.targets.spacing ? 1 : 0);
}

void bind_splat_chunk(const gl::Program& p, const VisibleChunk& v, const SplatSettings& s, bool spacing) {
  const gl::Buffer* normals = s.shading ? v.gpu->find({AttributeKind::Normal, s.normal_k}) : nullptr;
  const GpuCloud& c = *v.gpu;
  static_assert(kSplatNeighbors == kGapSpacingNeighbours, "the splats' footprint is the points' spacing");
  const gl::Buffer* radii = s.splat_size || spacing ? c.find({AttributeKind::SplatRadius, s.splat_k}) : nullptr;
  if (spacing && !radii) throw GLError("points: the points' spacing was not uploaded");
  bind_chunk(p, v, s.color_source,
             {{2, normals},
              {6, s.opacity_draws ? c.find({AttributeKind::PointId}) : nullptr},
              {7, radii},
              {8, s.opacity_draws ? c.find({AttributeKind::SplatOpacity}) : nullptr}});
  if (spacing) glUniform1f(p.location("u_spacing_scale"), view_scale(v));
}

// size_mode splat and spacing size each splat by its point's SplatRadius
// (a Gaussian splat's footprint; plain points: their mean distance to 8
// neighbours, capped at twice their neighbours' median).
bool sized_by_radius(const ParamValues& p) {
  const std::string mode = p.get_enum_name("size_mode");
  return mode == "splat" || mode == "spacing";
}

class Points final : public Mark {
 public:
  AttributeSet attributes(const ParamValues& p) const override {
    AttributeSet set = color_attributes(ColorSource(p.get_enum("color_source")));
    if (p.get_enum("shading") != 0) set.insert({AttributeKind::Normal, p.get_int("normal_neighbors")});
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    if (sized_by_radius(p)) set.insert({AttributeKind::SplatRadius, kSplatNeighbors});
    if (p.get_bool("opacity_draws")) {
      set.insert({AttributeKind::SplatOpacity});
      set.insert({AttributeKind::PointId});
    }
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override {
    const float diameter = p.get_enum("size_mode") == 0 ? float(p.get_float("point_size")) : kMaxSplatPixels;
    return {0.0, 0.5f * diameter + 1.0f};
  }

  // The compute rasterizer places splats by their frame pixel (less the
  // tile's origin, exactly); GL_POINTS by the frame's viewport moved by it,
  // with flat attributes: both the frame's bytes in every tile.
  bool draws_tiles(const ParamValues&) const override { return true; }

  void draw(const MarkContext& ctx, const ParamValues& p) const override {
    SplatSettings s;
    s.world_size = p.get_enum_name("size_mode") != "pixels";
    s.splat_size = sized_by_radius(p);
    s.splat_k = kSplatNeighbors;
    if (p.get_enum_name("size_mode") == "spacing") {
      s.radius_diameters = 1.0f;
      s.min_pixels = float(p.get_float("point_size"));
    }
    s.opacity_draws = p.get_bool("opacity_draws");
    s.point_size = float(p.get_float("point_size"));
    s.world_diameter = float(p.get_float("world_size"));
    s.color_source = ColorSource(p.get_enum("color_source"));
    s.constant_color = p.get_color("color");
    s.shading = p.get_enum("shading") != 0;
    s.shading_strength = float(p.get_float("shading_strength"));
    s.light_dir = view_light_direction(p, *ctx.camera);
    s.normal_k = p.get_int("normal_neighbors");
    if (draws_queue(ctx, p))
      for (const VisibleChunk& v : ctx.chunks) s.queue_counts.push_back(queue_count(v, p));
    const std::string rasterizer = resolved_rasterizer(p);
    if (rasterizer == "native")
      draw_splats_native(ctx, s);
    else if (rasterizer == "compute")
      draw_splats_compute(ctx, s);
    else
      draw_splats_gl(ctx, s);
  }

 private:
  // native, or the GL method (compute, gl_points); auto by render/backend.h.
  static std::string resolved_rasterizer(const ParamValues& p) {
    if (chosen_backend(p) == Backend::Native) return "native";
    return p.get_enum_name("gl_method");
  }
};

const MarkRegistration registration{{
    Schema{"points",
           "Points",
           "Draws the segment's points as round splats into its own colour and depth images.",
           {
               // Once one list: compute, gl_points, native, auto (the points'
               // GL methods are gl_method now, rasterizer as on every mark).
               items_changed(rasterizer_param("gl: GL draws the splats, by gl_method; native: the compute rules on "
                                              "the CPU's threads (the same images as compute)"),
                             {"compute", "gl_points", "native", "auto"},
                             {{"compute", "gl", "gl_method", "compute"}, {"gl_points", "gl", "gl_method", "gl_points"}}),
               only_when(enum_param("gl_method", {"compute", "gl_points"}, 0,
                                    "How GL draws the splats (rasterizer gl, or auto on a GPU): compute: compute-shader "
                                    "splatting (deterministic ties); gl_points: conventional GL points"),
                         "rasterizer", {"gl", "auto"}),
               enum_param("size_mode", {"pixels", "world", "splat", "spacing"}, 0,
                          "pixels: one size on screen; world: one size in scene units, projected by the camera; "
                          "splat: a Gaussian-splat capture's own footprint: twice 2 sqrt of the product of its two "
                          "largest scales, scene units (plain points: twice the mean distance to 8 neighbours), "
                          "capped at 32 px; spacing: as wide as the point's own spacing (its mean distance to 8 "
                          "neighbours, at most twice theirs), so a scan's gaps close where it is sparse on screen, "
                          "and at least point_size, capped at 32 px. world and splat as the brush splats' "
                          "size_mode; pixels is no size from the neighbours (their resolution)"),
               only_when(float_param("point_size", 2.0, 0.5, 32.0, "px",
                                     "Splat diameter in pixels (size_mode = pixels; spacing: the least)"),
                         "size_mode", {"pixels", "spacing"}),
               only_when(float_param("world_size", 0.05, 0.0001, 100.0, "m",
                                     "Splat diameter in scene units (size_mode = world); capped at 32 px on screen"),
                         "size_mode", {"world"}),
               color_source_param(),
               color_param("color", {0.8, 0.8, 0.8, 1.0}, "Constant color (display sRGB)"),
               enum_param("shading", {"none", "diffuse"}, 0,
                          "Light the points by their normals (the cloud's own, else estimated from neighbours, once)"),
               only_when(float_param("shading_strength", 0.7, 0.0, 1.0, "",
                                     "How dark surfaces turned away from the light get (diffuse shading)"),
                         "shading", {"diffuse"}),
               // Camera by default, as the points mark has always lit; world and
               // scene_sun (the host's sun lamp) as the other marks and mesh surfaces.
               only_when(enum_param("light_space", {"world", "camera", "scene_sun"}, 1,
                                    "camera: the light moves with the view; world: it stays with the scene; "
                                    "scene_sun: as world, from the host scene's sun lamp (Blender), so scans, "
                                    "meshes and the other marks share one light"),
                         "shading", {"diffuse"}),
               only_when(light_azimuth_param(135.0), "shading", {"diffuse"}),
               only_when(light_elevation_param(45.0), "shading", {"diffuse"}),
               only_when(int_param("normal_neighbors", 16, 3, 64, "",
                                   "Neighbours the normals are estimated from where a cloud has none (PCA, seed 001 eq. 1)"),
                         "shading", {"diffuse"}),
               density_mode_param(),
               queue_level_param(0.5),
               bool_param("opacity_draws", false,
                          "A Gaussian-splat capture's opacity is the chance each splat is drawn (hashed from its "
                          "point id: the same splats in every frame; a faint haze thins out instead of covering; "
                          "plain points: all drawn)"),
           }},
    [] { return std::make_unique<Points>(); }}};

}  // namespace

void draw_splats_compute(const MarkContext& ctx, const SplatSettings& s) {
  const bool int64 = ctx.targets.int64_atomics;
  std::vector<std::vector<std::string>> passes;
  if (int64)
    passes = {{"INT64_ATOMICS", "PASS_DEPTH"}, {"INT64_ATOMICS", "PASS_COLOR"}};
  else
    passes = {{"PASS_DEPTH"}, {"PASS_KEY"}, {"PASS_COLOR"}};
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, ctx.targets.depth_keys->id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, ctx.targets.keys->id());
  glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  if (ctx.targets.spacing)
    glBindImageTexture(2, ctx.targets.spacing->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  for (const auto& defines : passes) {
    const gl::Program& p = ctx.shaders->compute("points.comp", defines);
    p.use();
    set_splat_uniforms(p, ctx, s);
    const bool queue = !s.queue_counts.empty();
    glUniform1i(p.location("u_queue"), queue ? 1 : 0);
    for (size_t c = 0; c < ctx.chunks.size(); ++c) {
      const VisibleChunk& v = ctx.chunks[c];
      bind_splat_chunk(p, v, s, ctx.targets.spacing != nullptr);
      uint32_t count = v.chunk->count;
      if (queue) {
        const gl::Buffer* order = v.gpu->find({AttributeKind::QueueOrder});
        if (!order) throw GLError("points: the queue order was not uploaded");
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, order->id());
        count = s.queue_counts[c];
        glUniform1ui(p.location("u_count"), count);
      }
      if (count > 0) glDispatchCompute((count + 127) / 128, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
}

void draw_splats_gl(const MarkContext& ctx, const SplatSettings& s) {
  const gl::Program& p = ctx.shaders->graphics("points.vert", "points.frag");
  const Rect& clip = ctx.clip;
  glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.spacing ? ctx.targets.spacing_fbo : ctx.targets.fbo);
  // A square power-of-two viewport over the images and the widest splat's
  // radius around them (points.vert: exact, render/exact_raster.h).
  const ExactRaster raster = exact_raster(ctx.targets, 0.5f * kMaxSplatPixels + 1.0f);
  raster.apply();
  glEnable(GL_SCISSOR_TEST);
  glScissor(clip.min.x, clip.min.y, clip.size().x, clip.size().y);
  const float zero = 0.0f;
  glClearBufferfv(GL_DEPTH, 0, &zero);  // reversed Z: 0 is the far end
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glEnable(GL_PROGRAM_POINT_SIZE);
  p.use();
  set_splat_uniforms(p, ctx, s);
  raster.set_uniforms(p);
  for (size_t c = 0; c < ctx.chunks.size(); ++c) {
    const VisibleChunk& v = ctx.chunks[c];
    bind_splat_chunk(p, v, s, ctx.targets.spacing != nullptr);
    glBindVertexArray(v.gpu->vao.id());
    if (s.queue_counts.empty()) {
      glDrawArrays(GL_POINTS, GLint(v.chunk->first), GLsizei(v.chunk->count));
    } else if (s.queue_counts[c] > 0) {
      // The queue order as the element buffer: element = chunk-local index,
      // + base vertex = the point's index (gl_VertexID).
      const gl::Buffer* order = v.gpu->find({AttributeKind::QueueOrder});
      if (!order) throw GLError("points: the queue order was not uploaded");
      glVertexArrayElementBuffer(v.gpu->vao.id(), order->id());
      glDrawElementsBaseVertex(GL_POINTS, GLsizei(s.queue_counts[c]), GL_UNSIGNED_INT,
                               reinterpret_cast<const void*>(size_t(v.chunk->first) * sizeof(uint32_t)),
                               GLint(v.chunk->first));
      glVertexArrayElementBuffer(v.gpu->vao.id(), 0);
    }
  }
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

}  // namespace pointnpr
