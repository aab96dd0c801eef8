#pragma once
// Small helpers shared by the filters in this folder.
#include <cmath>
#include <glm/glm.hpp>

#include "render/filter.h"

namespace pointnpr::filters {

inline void bind_image(GLuint unit, const gl::Texture& t, GLenum access) {
  glBindImageTexture(unit, t.id(), 0, GL_FALSE, 0, access, t.format());
}

// `r` grown by `by` rows above and below (the first pass of a separable
// kernel must cover the rows the second pass reads).
inline Rect grown_rows(const Rect& r, int by, glm::ivec2 limit) {
  if (r.empty()) return r;
  return Rect{{r.min.x, std::max(r.min.y - by, 0)}, {r.max.x, std::min(r.max.y + by, limit.y)}};
}

// Radius of a truncated Gaussian kernel (3 sigma: 99.7 % of the weight).
inline int gauss_radius(double sigma) { return sigma <= 0.0 ? 0 : int(std::ceil(3.0 * sigma)); }

inline void set_color(const gl::Program& p, const char* name, glm::vec4 c) {
  glUniform4f(p.location(name), c.r, c.g, c.b, c.a);
}

}  // namespace pointnpr::filters
