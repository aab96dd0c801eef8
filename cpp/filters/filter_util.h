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

// The smoothed structure tensor of `input` over `area` (kuwahara.comp's
// passes; Kyprianidis et al.'s flow field, which the Kuwahara filter and
// the flow-guided DoG read): the tensor over `area` grown by `radius`,
// smoothed along x then y (Gaussian `sigma`) into `smooth`; `tensor` and
// `smooth_x` are scratch.
inline void structure_tensor(const FilterContext& ctx, const gl::Texture& input, const Rect& area, int radius,
                             float sigma, const gl::Texture& tensor, const gl::Texture& smooth_x,
                             const gl::Texture& smooth) {
  struct Pass {
    const char* define;
    const gl::Texture* in;
    const gl::Texture* out;
    Rect rect;
  };
  const Pass passes[] = {
      {"PASS_TENSOR", &input, &tensor, area.grown(radius, ctx.image_size)},
      {"PASS_SMOOTH_X", &tensor, &smooth_x, grown_rows(area, radius, ctx.image_size)},
      {"PASS_SMOOTH_Y", &smooth_x, &smooth, area},
  };
  for (const Pass& pass : passes) {
    const gl::Program& prog = ctx.shaders->compute("kuwahara.comp", {pass.define});
    prog.use();
    glUniform1f(prog.location("u_sigma"), sigma);
    glUniform1i(prog.location("u_radius"), radius);
    bind_image(0, *pass.in, GL_READ_ONLY);
    bind_image(1, *pass.out, GL_WRITE_ONLY);
    dispatch_rect(prog, pass.rect);
  }
}

inline void set_color(const gl::Program& p, const char* name, glm::vec4 c) {
  glUniform4f(p.location(name), c.r, c.g, c.b, c.a);
}

}  // namespace pointnpr::filters
