#pragma once
// A box (chunk or mesh bounds) seen by the camera, in double: the culling
// of chunks and meshes share it.
#include <glm/glm.hpp>

#include "render/filter.h"  // Rect
#include "scene/camera.h"

namespace pointnpr {

struct ProjectedBox {
  bool all_near = true, all_far = true;  // every corner before the near / beyond the far plane
  bool crosses_near = false;             // a corner behind (half) the near plane: no rectangle
  double depth_min = 0.0, depth_max = 0.0;
  glm::dvec2 corners[8]{};               // window positions (frame pixels), unless crosses_near
  glm::dvec2 lo{0.0}, hi{0.0};           // their bounds

  // Conservative pixel rectangle grown by `margin`, inside the frame (the
  // whole frame where the box crosses the camera plane).
  Rect rect(glm::ivec2 frame, double margin) const;
  // Area of the convex hull of the corners (the continuous resolution
  // queue's M), by Andrew's monotone chain.
  double hull_area() const;
};

ProjectedBox project_box(const glm::dmat4& view_from_box, const glm::dvec3& lo, const glm::dvec3& hi,
                         const Camera& cam, glm::ivec2 frame);

}  // namespace pointnpr
