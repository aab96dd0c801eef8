#pragma once
// Synthetic scenes with known ground truth for the renderer tests.
#include <cstdint>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/mark.h"
#include "render/renderer.h"

namespace pointnpr::test {

// Points on a jittered grid filling the rectangle [x0,x1]x[y0,y1] at z,
// with one colour. Jitter is seeded by point index (deterministic).
inline std::shared_ptr<PointCloud> plane_cloud(double x0, double x1, double y0, double y1, double z, double spacing,
                                               glm::u8vec3 color, glm::dvec3 offset = glm::dvec3(0.0),
                                               double jitter = 0.0) {
  std::vector<double> pos;
  std::vector<uint8_t> col;
  uint32_t i = 0;
  for (double y = y0; y <= y1 + 1e-9; y += spacing)
    for (double x = x0; x <= x1 + 1e-9; x += spacing, ++i) {
      uint32_t h = i * 2654435761u;
      const double jx = jitter * (double((h >> 8) & 0xffff) / 65535.0 - 0.5);
      h = h * 1664525u + 1013904223u;
      const double jy = jitter * (double((h >> 8) & 0xffff) / 65535.0 - 0.5);
      pos.insert(pos.end(), {x + jx + offset.x, y + jy + offset.y, z + offset.z});
      col.insert(col.end(), {color.r, color.g, color.b});
    }
  PointCloudInput in;
  in.positions = pos;
  in.colors = col;
  return std::make_shared<PointCloud>(in);
}

inline Segment segment(const std::string& name, std::shared_ptr<PointCloud> cloud, Style style = {},
                       glm::dmat4 world_from_object = glm::dmat4(1.0)) {
  Segment s;
  s.name = name;
  s.style = std::move(style);
  s.instances.push_back({std::move(cloud), world_from_object});
  return s;
}

// A style drawing the points mark with `points` parameters.
inline Style style_with(std::map<std::string, std::vector<double>> points,
                        std::vector<std::pair<std::string, std::map<std::string, std::vector<double>>>> filters = {},
                        std::map<std::string, std::vector<double>> inpaint = {}) {
  Style s;
  s.set_mark("points", points);
  for (auto& [id, params] : filters) s.add_filter(id, params);
  s.inpaint = validate(inpaint_schema(), inpaint);
  return s;
}

// Camera at `eye` looking down -Z (identity rotation).
inline Camera front_camera(glm::dvec3 eye, glm::ivec2 size, double clip_start = 0.1, double clip_end = 1000.0,
                           double lens = 50.0) {
  glm::dmat4 world_from_camera(1.0);
  world_from_camera[3] = glm::dvec4(eye, 1.0);
  return Camera::perspective(world_from_camera, lens, 36.0, 24.0, SensorFit::Auto, 0.0, 0.0, clip_start, clip_end,
                             size);
}

inline RenderSettings settings(glm::ivec2 size, const std::string& composite = "inpaint", double time = 0.0) {
  RenderSettings s;
  s.width = size.x;
  s.height = size.y;
  s.time = time;
  const auto& items = composite_schema().params[0].items;
  const double mode = double(std::find(items.begin(), items.end(), composite) - items.begin());
  s.composite = validate(composite_schema(), {{"mode", {mode}}});
  return s;
}

// The points mark's rasterizers: its GL methods, native and auto.
enum class RasterizerKind { Compute, GlPoints, Native, Auto };

// Sets the points mark's `rasterizer` (and `gl_method`) in `params` to
// `kind`, by the single value it had before gl_method (read as rasterizer
// gl with that method, as a script giving it is).
inline void set_rasterizer(std::map<std::string, std::vector<double>>& params, RasterizerKind kind) {
  static const char* const names[] = {"compute", "gl_points", "native", "auto"};
  const Schema& schema = find_mark("points").schema;
  params.erase("gl_method");
  set_enum_item(schema, *schema.find("rasterizer"), names[int(kind)], params);
}

// `scene` with every points mark set to rasterizer `kind`.
inline Scene with_rasterizer(Scene scene, RasterizerKind kind) {
  for (Segment& seg : scene.segments) {
    if (seg.style.mark.info->schema.id != "points") continue;
    auto params = seg.style.mark.params.raw();
    set_rasterizer(params, kind);
    seg.style.set_mark("points", params);
  }
  return scene;
}

}  // namespace pointnpr::test
