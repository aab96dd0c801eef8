#pragma once
// Ink of marks drawn as GL primitives (strokes, sprites), blended
// order-independently and deterministically into three scratch images over
// the mark's clip: colour weighted by alpha (a sum), transmittance (a
// product) and the nearest depth (a minimum). Sums and products in a fixed
// primitive order give the same bytes in every run, whatever the order the
// marks were generated in. A fragment shader writes (rgb * a, a), (a) and
// (linear depth) to locations 0, 1, 2. resolve() lays the ink over paper
// into the segment's colour and depth (shaders/ink_resolve.comp).
#include <glm/vec4.hpp>

#include "render/exact_raster.h"
#include "render/mark.h"

namespace pointnpr {

class InkLayer {
 public:
  // Clears the ink over ctx.clip and builds its framebuffer (with the
  // frame's GL depth buffer, for depth tests against a depth pass).
  InkLayer(const MarkContext& ctx, const char* what);

  // GL state for drawing ink: its framebuffer, the exact viewport (the
  // marks draw tiles, render/exact_raster.h), scissor to the clip,
  // reversed-Z GEQUAL depth test when asked, no depth writes, the three
  // blend modes.
  void begin(bool depth_test, const ExactRaster& raster) const;
  void end() const;  // back to GL defaults
  // The three blend modes alone (for marks with their own raster state).
  static void blend_modes();

  // Ink over `paper` (display sRGB, alpha = its opacity over the surface)
  // into ctx.targets.color and .depth. With `surface`, ctx.targets.depth
  // holds a depth pass: the paper covers it and its depth wins; elsewhere
  // the ink's nearest depth.
  void resolve(glm::vec4 paper, bool surface) const;

  const gl::Texture& accum;   // RGBA32F
  const gl::Texture& reveal;  // R32F transmittance
  const gl::Texture& depth;   // R32F nearest linear depth

 private:
  const MarkContext& ctx_;
  gl::Framebuffer fbo_;
};

}  // namespace pointnpr
