#include "render/exact_raster.h"

#include <algorithm>
#include <cmath>

namespace pointnpr {

ExactRaster exact_raster(const MarkTargets& targets, float reach) {
  GLint dims[2] = {0, 0};
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
  const int largest = std::max(1, std::min(dims[0], dims[1]));
  const int images = std::max(targets.size.x, targets.size.y);
  ExactRaster r;
  r.origin = targets.origin;
  const int wanted = int(std::ceil(std::max(reach, 0.0f))) + 1;
  while (r.side < images + 2 * wanted && r.side < largest) r.side *= 2;
  r.side = std::min(r.side, largest);
  r.margin = std::clamp((r.side - images) / 2, 0, wanted);
  return r;
}

void ExactRaster::apply() const { glViewport(-margin, -margin, side, side); }

void ExactRaster::set_uniforms(const gl::Program& p) const {
  glUniform2i(p.location("u_origin"), origin.x, origin.y);
  // The window position of NDC 0: x_w = ndc * half + (half - margin) is the
  // shader's window position exactly (half a power of two).
  glUniform1f(p.location("u_raster_center"), 0.5f * float(side) - float(margin));
  glUniform1f(p.location("u_raster_half"), 0.5f * float(side));
}

}  // namespace pointnpr
