#include "render/filter.h"

#include <algorithm>
#include <map>

#include "core/error.h"
#include "scene/camera.h"

#include <glm/gtc/type_ptr.hpp>

namespace pointnpr {

Rect Rect::grown(int by, glm::ivec2 limit) const {
  if (empty()) return *this;
  Rect r{glm::max(min - by, glm::ivec2(0)), glm::min(max + by, limit)};
  return r;
}

Rect Rect::united(const Rect& o) const {
  if (empty()) return o;
  if (o.empty()) return *this;
  return {glm::min(min, o.min), glm::max(max, o.max)};
}

SurfaceFrame make_surface_frame(const Camera& camera, glm::ivec2 image_size, const glm::dmat4& world_from_anchor) {
  // Blender's projections have no x/y term in w: w = P32 z + P33 with z = -d.
  // Solving P's first two rows for view x, y gives terms constant and linear
  // in d, each affine in the pixel position (through ndc = 2 q / size - 1).
  const glm::dmat4& P = camera.projection;
  const double a = P[0][0], b = P[1][0], c = P[0][1], e = P[1][1];  // [row][col] = P[col][row]
  const double det = a * e - b * c;
  SurfaceFrame f;
  if (std::abs(det) < 1e-300 || image_size.x <= 0 || image_size.y <= 0) return f;
  auto solve = [&](double rx, double ry) { return glm::dvec2(e * rx - b * ry, -c * rx + a * ry) / det; };
  auto at = [&](double px, double py, bool per_depth) {
    const double nx = 2.0 * px / image_size.x - 1.0, ny = 2.0 * py / image_size.y - 1.0;
    if (per_depth) return solve(P[2][0] - nx * P[2][3], P[2][1] - ny * P[2][3]);
    return solve(nx * P[3][3] - P[3][0], ny * P[3][3] - P[3][1]);
  };
  for (int per_depth = 0; per_depth < 2; ++per_depth) {
    const glm::dvec2 o = at(0, 0, per_depth), dx = at(1, 0, per_depth) - o, dy = at(0, 1, per_depth) - o;
    (per_depth ? f.x1 : f.x0) = glm::vec3(dx.x, dy.x, o.x);
    (per_depth ? f.y1 : f.y0) = glm::vec3(dx.y, dy.y, o.y);
  }
  f.object_from_view = glm::mat4(glm::inverse(camera.view_from_world * world_from_anchor));
  return f;
}

void set_surface_uniforms(const gl::Program& program, const SurfaceFrame& frame) {
  glUniform3fv(program.location("u_surface_x0"), 1, glm::value_ptr(frame.x0));
  glUniform3fv(program.location("u_surface_x1"), 1, glm::value_ptr(frame.x1));
  glUniform3fv(program.location("u_surface_y0"), 1, glm::value_ptr(frame.y0));
  glUniform3fv(program.location("u_surface_y1"), 1, glm::value_ptr(frame.y1));
  glUniformMatrix4fv(program.location("u_object_from_view"), 1, GL_FALSE, glm::value_ptr(frame.object_from_view));
}

const std::vector<const FilterInfo*>& registered_filters() { return Registry<FilterInfo>::instance().all(); }

const FilterInfo& find_filter(const std::string& id) { return Registry<FilterInfo>::instance().find(id); }

glm::ivec2& pixel_origin() {
  static glm::ivec2 origin{0, 0};
  return origin;
}

void dispatch_rect(const gl::Program& program, const Rect& rect) {
  if (rect.empty()) return;
  program.use();
  glUniform2i(program.location("u_origin"), pixel_origin().x, pixel_origin().y);
  glUniform2i(program.location("u_rect_min"), rect.min.x, rect.min.y);
  glUniform2i(program.location("u_rect_max"), rect.max.x, rect.max.y);
  const glm::ivec2 s = rect.size();
  glDispatchCompute(GLuint((s.x + 15) / 16), GLuint((s.y + 15) / 16), 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                  GL_SHADER_STORAGE_BARRIER_BIT);
}

}  // namespace pointnpr
