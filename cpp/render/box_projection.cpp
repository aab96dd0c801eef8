#include "render/box_projection.h"

#include <algorithm>
#include <limits>

namespace pointnpr {

ProjectedBox project_box(const glm::dmat4& view_from_box, const glm::dvec3& lo, const glm::dvec3& hi,
                         const Camera& cam, glm::ivec2 frame) {
  ProjectedBox b;
  b.depth_min = std::numeric_limits<double>::max();
  b.lo = glm::dvec2(std::numeric_limits<double>::max());
  b.hi = glm::dvec2(-std::numeric_limits<double>::max());
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const glm::dvec4 v = view_from_box * glm::dvec4(corner, 1.0);
    const double dist = -v.z;
    b.depth_min = std::min(b.depth_min, dist);
    b.depth_max = std::max(b.depth_max, dist);
    b.all_near = b.all_near && dist < cam.clip_start;
    b.all_far = b.all_far && dist > cam.clip_end;
    if (!cam.orthographic && dist < cam.clip_start * 0.5) {
      b.crosses_near = true;
      continue;
    }
    const glm::dvec4 clip = cam.projection * v;
    const glm::dvec2 win = (glm::dvec2(clip) / clip.w * 0.5 + 0.5) * glm::dvec2(frame);
    b.lo = glm::min(b.lo, win);
    b.hi = glm::max(b.hi, win);
    b.corners[c] = win;
  }
  return b;
}

Rect ProjectedBox::rect(glm::ivec2 frame, double margin) const {
  if (crosses_near) return Rect{{0, 0}, frame};
  Rect r;
  r.min = glm::ivec2(glm::max(glm::floor(lo - margin), glm::dvec2(0.0)));
  r.max = glm::ivec2(glm::min(glm::ceil(hi + margin), glm::dvec2(frame)));
  return r;
}

double ProjectedBox::hull_area() const {
  glm::dvec2 p[8];
  std::copy(std::begin(corners), std::end(corners), p);
  std::sort(std::begin(p), std::end(p), [](glm::dvec2 a, glm::dvec2 b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  auto cross = [](glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
  glm::dvec2 hull[16];
  int k = 0;
  for (int i = 0; i < 8; ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
    hull[k++] = p[i];
  }
  for (int i = 6, t = k + 1; i >= 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0.0) --k;
    hull[k++] = p[i];
  }
  double area = 0.0;
  for (int i = 0; i + 1 < k; ++i) area += hull[i].x * hull[i + 1].y - hull[i + 1].x * hull[i].y;
  return std::abs(area) * 0.5;
}


}  // namespace pointnpr
