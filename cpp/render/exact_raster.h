#pragma once
// GL marks drawn in tiles (render/tiling.h) with the same bytes in every
// tile: the GL's viewport transform and attribute interpolation round
// differently when a tile moves the viewport's origin, so these marks
//  - put every vertex at its frame position on a 1/256 pixel grid, less the
//    tile's integer origin, with w = 1, through a square power-of-two
//    viewport: each step of the viewport transform is then exact (multiples
//    of 1/256 under 2^15), and the rasterizer's coverage is the frame's;
//  - compute what varies over a primitive (texture coordinates, depth) per
//    fragment from its frame pixel (gl_FragCoord + origin) and flat data.
// The viewport reaches `margin` pixels beyond the images on every side, so
// no primitive that reaches the images is clipped (clipping makes new,
// inexact vertices). shaders/exact_window.glsl is the shader side.
#include "gl/shaders.h"
#include "render/mark.h"

namespace pointnpr {

struct ExactRaster {
  glm::ivec2 origin{0, 0};  // the images' frame pixel (0, 0)
  int side = 1;             // the viewport's side, a power of two
  int margin = 0;           // viewport pixels beyond the images' bottom left

  // The viewport (-margin, -margin, side, side).
  void apply() const;
  // u_origin, u_raster_center, u_raster_half of shaders/exact_window.glsl.
  void set_uniforms(const gl::Program& program) const;
};

// For primitives reaching at most `reach` pixels beyond the images' edges
// that matter (a mark's extent): the margin is that, or what the GL's
// largest viewport leaves around images that large.
ExactRaster exact_raster(const MarkTargets& targets, float reach);

}  // namespace pointnpr
