#include "render/mark.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "geometry/analysis.h"
#include "gl/device.h"
#include "scene/camera.h"

namespace pointnpr {

const std::vector<const MarkInfo*>& registered_marks() { return Registry<MarkInfo>::instance().all(); }

const MarkInfo& find_mark(const std::string& id) { return Registry<MarkInfo>::instance().find(id); }

ParamSpec color_source_param() {
  // "auto" comes last so stored enum indices of older files keep their meaning.
  return enum_param("color_source", {"rgb", "intensity", "classification", "constant", "auto"}, 4,
                    "Where point colours come from; auto: RGB, else intensity, else the class palette; a cloud "
                    "lacking the chosen one uses the constant colour");
}

AttributeSet color_attributes(ColorSource source) {
  switch (source) {
    case ColorSource::Rgb: return {{AttributeKind::Color}};
    case ColorSource::Intensity: return {{AttributeKind::Intensity}};
    case ColorSource::Classification: return {{AttributeKind::Classification}};
    case ColorSource::Constant: return {};
    case ColorSource::Auto: return {{AttributeKind::AutoColor}};
  }
  return {};
}

ColorSource resolve_color_source(ColorSource source, const GpuCloud& g) {
  auto has = [&](AttributeKind a) { return g.find({a}) != nullptr; };
  switch (source) {
    case ColorSource::Rgb: return has(AttributeKind::Color) ? source : ColorSource::Constant;
    case ColorSource::Intensity: return has(AttributeKind::Intensity) ? source : ColorSource::Constant;
    case ColorSource::Classification: return has(AttributeKind::Classification) ? source : ColorSource::Constant;
    case ColorSource::Constant: return source;
    case ColorSource::Auto:
      if (has(AttributeKind::Color)) return ColorSource::Rgb;
      if (has(AttributeKind::Intensity)) return ColorSource::Intensity;
      if (has(AttributeKind::Classification)) return ColorSource::Classification;
      return ColorSource::Constant;
  }
  return ColorSource::Constant;
}

ParamSpec paper_color_param(glm::dvec4 def, const std::string& marks) {
  return color_param("paper_color", def,
                     "Colour under the " + marks + " where the surface is (alpha: its opacity; 0 leaves " + marks +
                         " only)");
}

ParamSpec density_mode_param() {
  return enum_param("density_mode", {"all_points", "constant_on_screen"}, 0,
                    "all_points: every point of the visible chunks; constant_on_screen: the continuous resolution "
                    "queue, each chunk drawing the first queue_level x its projected area (pixels) of its points in a "
                    "fixed random order, so the density of marks on screen stays the same at any distance");
}

ParamSpec queue_level_param(double default_level) {
  return only_when(float_param("queue_level", default_level, 0.0, 4.0, "",
                               "Points drawn per pixel of each chunk's projected area (constant_on_screen): its bounding box's, or "
                               "the area its points sample where that is less"),
                   "density_mode", {"constant_on_screen"});
}

void set_mark_clip(const Rect& clip) {
  glEnable(GL_SCISSOR_TEST);
  glScissor(clip.min.x, clip.min.y, clip.size().x, clip.size().y);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
}

void restore_raster_defaults() {
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

MarkRasterState::MarkRasterState(const MarkTargets& targets, const Rect& clip) {
  set_frame_viewport(targets);
  set_mark_clip(clip);
}

MarkRasterState::~MarkRasterState() { restore_raster_defaults(); }

void upload_cpu_mark(const MarkTargets& targets, const Rect& clip, const float* rgba, const float* depth,
                     const std::vector<glm::ivec2>& row_span, std::optional<Rect>* coverage, const char* what) {
  const glm::ivec2 size = clip.max - clip.min;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glTextureSubImage2D(targets.color->id(), 0, clip.min.x, clip.min.y, size.x, size.y, GL_RGBA, GL_FLOAT, rgba);
  glTextureSubImage2D(targets.depth->id(), 0, clip.min.x, clip.min.y, size.x, size.y, GL_RED, GL_FLOAT, depth);
  gl::check_gl((std::string(what) + ": native upload").c_str());
  if (!coverage) return;
  Rect covered{{size.x, size.y}, {-1, -1}};
  for (int y = 0; y < size.y; ++y) {
    const glm::ivec2 span = row_span[size_t(y)];
    if (span.y < 0) continue;
    covered.min = glm::min(covered.min, glm::ivec2(span.x, y));
    covered.max = glm::max(covered.max, glm::ivec2(span.y + 1, y + 1));
  }
  *coverage = covered.empty() ? Rect{} : Rect{covered.min + clip.min, covered.max + clip.min};
}

bool queue_enabled(const ParamValues& p) {
  return p.raw().count("density_mode") && p.get_enum_name("density_mode") == "constant_on_screen";
}

bool draws_queue(const VisibleChunk& v, const ParamValues& p) {
  return queue_enabled(p) || v.budget_count < v.chunk->count;
}

bool draws_queue(const MarkContext& ctx, const ParamValues& p) {
  return std::any_of(ctx.chunks.begin(), ctx.chunks.end(), [&p](const VisibleChunk& v) { return draws_queue(v, p); });
}

uint32_t queue_count(const VisibleChunk& v, const ParamValues& p) {
  const uint32_t n = std::min(v.chunk->count, v.budget_count);
  if (!queue_enabled(p) || !(v.screen_area >= 0.0)) return n;
  const double wanted = std::floor(p.get_float("queue_level") * v.screen_area + 0.5);
  return wanted >= double(n) ? n : uint32_t(std::max(wanted, 0.0));
}

ParamSpec light_space_param(int default_space) {
  return enum_param("light_space", {"world", "camera", "scene_sun"}, default_space,
                    "world: the light stays with the scene (marks do not change as the camera moves); "
                    "camera: it moves with the view; scene_sun: as world, from the direction of the host "
                    "scene's sun lamp (Blender), so scans and meshes share one light");
}

Schema with_surface_light(Schema schema, const std::string& what, double strength) {
  const std::vector<std::string> lit{"diffuse", "auto"};
  schema.params.push_back(added_later(
      enum_param("shading", {"none", "diffuse", "auto"}, 2,
                 "Light " + what + " (two-sided diffuse): none; diffuse; auto: diffuse where the points have no "
                 "colour of their own (a colourless scan reads as a shaded shape), none where they have"),
      {0.0}));
  schema.params.push_back(only_when(
      float_param("shading_strength", strength, 0.0, 1.0, "", "How dark surfaces turned away from the light get"),
      "shading", lit));
  schema.params.push_back(only_when(light_space_param(1), "shading", lit));
  schema.params.push_back(only_when(light_azimuth_param(135.0), "shading", lit));
  schema.params.push_back(only_when(light_elevation_param(45.0), "shading", lit));
  return schema;
}

bool lit_by_shading(const ParamValues& p, ColorSource resolved) {
  const std::string& shading = p.get_enum_name("shading");
  return shading == "diffuse" || (shading == "auto" && resolved == ColorSource::Constant);
}

ParamSpec light_azimuth_param(double default_deg) {
  return float_param("light_azimuth", default_deg, -180.0, 180.0, "deg",
                     "Light direction: around world Z (world), or around the view axis (camera; 0 from the right)");
}

ParamSpec light_elevation_param(double default_deg) {
  return float_param("light_elevation", default_deg, -90.0, 90.0, "deg",
                     "Light direction: above the XY plane (world), or away from the view axis (camera; 0: "
                     "from the camera)");
}

glm::dvec3 world_direction(double azimuth_deg, double elevation_deg) {
  const double a = glm::radians(azimuth_deg), e = glm::radians(elevation_deg);
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

glm::vec3 view_light_direction(const ParamValues& p, const Camera& cam) {
  if (p.get_enum_name("light_space") != "camera")
    return glm::normalize(glm::vec3(glm::dmat3(cam.view_from_world) *
                                    world_direction(p.get_float("light_azimuth"), p.get_float("light_elevation"))));
  const double a = glm::radians(p.get_float("light_azimuth")), e = glm::radians(p.get_float("light_elevation"));
  return {float(std::sin(e) * std::cos(a)), float(std::sin(e) * std::sin(a)), float(std::cos(e))};
}

std::shared_ptr<const PointCloud> chunk_cloud(const VisibleChunk& v, const char* what) {
  std::shared_ptr<const PointCloud> cloud = v.gpu->source.lock();
  if (!cloud) throw GLError(std::string(what) + ": a visible chunk's cloud is gone");
  return cloud;
}

float median_spacing(const VisibleChunk& v, int k, float otherwise) {
  const std::shared_ptr<const PointCloud> cloud = v.gpu->source.lock();
  if (!cloud || cloud->size() == 0) return otherwise;
  const float median = cloud->analysis().surface_resolution(k)->median_r;
  return median > 0.0f ? median : otherwise;
}

float sparse_spacing(const VisibleChunk& v, int k, float otherwise) {
  const std::shared_ptr<const PointCloud> cloud = v.gpu->source.lock();
  if (!cloud || cloud->size() == 0) return otherwise;
  const float sparse = cloud->analysis().surface_resolution(k)->sparse_r;
  return sparse > 0.0f && std::isfinite(sparse) ? sparse : otherwise;
}

float view_scale(const VisibleChunk& v) {
  // A camera has none: the instance's.
  return std::cbrt(std::abs(glm::determinant(glm::mat3(v.view_from_chunk))));
}

float view_spacing(const VisibleChunk& v, int k) {
  const std::shared_ptr<const PointCloud> cloud = v.gpu->source.lock();
  if (!cloud || cloud->size() == 0) return 0.0f;
  const float spacing = cloud->analysis().surface_resolution(k)->sparse_r * view_scale(v);
  return std::isfinite(spacing) ? spacing : 0.0f;
}

void bind_chunk(const gl::Program& p, const VisibleChunk& v, ColorSource source,
                const std::vector<std::pair<int, const gl::Buffer*>>& extra) {
  const GpuCloud& g = *v.gpu;
  source = resolve_color_source(source, g);
  const gl::Buffer* color = nullptr;
  if (source == ColorSource::Rgb) color = g.find({AttributeKind::Color});
  if (source == ColorSource::Intensity) color = g.find({AttributeKind::Intensity});
  if (source == ColorSource::Classification) color = g.find({AttributeKind::Classification});
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.positions.id());
  // Unused bindings get the positions: a valid buffer the shader never reads.
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, color ? color->id() : g.positions.id());
  for (const auto& [binding, buffer] : extra)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), buffer ? buffer->id() : g.positions.id());
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_chunk)));
  glUniformMatrix3fv(p.location("u_normal_matrix"), 1, GL_FALSE, glm::value_ptr(normal_matrix));
  glUniform1i(p.location("u_color_source"), int(source));
  glUniform1f(p.location("u_intensity_scale"), g.intensity_scale);
  glUniformMatrix4fv(p.location("u_view_from_chunk"), 1, GL_FALSE, glm::value_ptr(v.view_from_chunk));
  glUniform1ui(p.location("u_first"), v.chunk->first);
  glUniform1ui(p.location("u_count"), v.chunk->count);
  glUniform1ui(p.location("u_key_base"), v.key_base);
}

}  // namespace pointnpr
