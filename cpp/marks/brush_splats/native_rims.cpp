// The rims of brushes in front of another surface (brush_splats.h,
// shaders/brush_rims.glsl) for both paths: the camera's numbers, and the
// native passes' rims over the host images, rows in parallel.
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/glsl.h"
#include "marks/brush_splats/brush_splats.h"
#include "scene/camera.h"

namespace pointnpr {

RimReach rim_reach(const MarkContext& ctx, const ParamValues& p) {
  const Camera& cam = *ctx.camera;
  const float pixel = float(1.0 / cam.pixels_per_unit(1.0, frame_size(ctx.targets).y));  // at depth 1
  RimReach r;
  (cam.orthographic ? r.footprint0 : r.footprint1) = pixel;
  r.reach = int(std::ceil(p.get_float("max_radius")));
  return r;
}

namespace brush_rims {
using namespace glsl;

// What the shared kernel reads: the resolved images of the clip.
struct Kernels {
  const float* color;
  const float* depth;
  const float* offset;
  ivec2 size;
  vec4 rim_color(ivec2 p) const {
    const float* c = color + 4 * (size_t(p.y) * size_t(size.x) + size_t(p.x));
    return vec4(c[0], c[1], c[2], c[3]);
  }
  float rim_depth(ivec2 p) const { return depth[size_t(p.y) * size_t(size.x) + size_t(p.x)]; }
  float rim_offset(ivec2 p) const { return offset[size_t(p.y) * size_t(size.x) + size_t(p.x)]; }
  bool rim_in(ivec2 p) const { return p.x >= 0 && p.y >= 0 && p.x < size.x && p.y < size.y; }
#include "brush_rims.glsl"
};

}  // namespace brush_rims

void fill_rims_native(const RimReach& rim, float* color, const float* depth, const float* offset, glm::ivec2 size,
                      const std::vector<glm::ivec2>& row_span, float* scratch) {
  brush_rims::Kernels k{color, depth, offset, size};
  const brush_rims::Kernels::RimRule rule{rim.footprint0, rim.footprint1, kSteepestSurfaceSlope, rim.reach};
  // Into the scratch (the rims read their neighbours as resolved), then
  // back; a pixel left as it was is marked by a negative alpha there.
  auto rows = [&](bool back) {
    tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y < r.end(); ++y) {
        const glm::ivec2 span = row_span[size_t(y)];
        for (int x = span.x; x <= span.y; ++x) {
          const size_t q = 4 * (size_t(y) * size_t(size.x) + size_t(x));
          if (back) {
            if (scratch[q + 3] >= 0.0f) std::copy(scratch + q, scratch + q + 4, color + q);
            continue;
          }
          scratch[q + 3] = -1.0f;
          const float a = color[q + 3];
          if (!(a > 0.0f && a < 1.0f)) continue;  // (the kernel returns these as they are)
          const glm::vec4 c = k.rim_fill(glm::ivec2(x, y), rule);
          for (int ch = 0; ch < 4; ++ch) scratch[q + size_t(ch)] = c[ch];
        }
      }
    });
  };
  rows(false);
  rows(true);
}

}  // namespace pointnpr
