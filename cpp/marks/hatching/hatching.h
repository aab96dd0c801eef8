#pragma once
// The hatching mark's two stroke backends (hatching.cpp: GL; native.cpp:
// the CPU's threads), drawing what one frame resolved once: the settings
// both read (settings.h) and the depth pass both test against.
#include "marks/hatching/settings.h"
#include "marks/points/points.h"
#include "render/mark.h"

namespace pointnpr::hatching {

struct StrokePass {
  HatchingSettings select{};          // what each point draws (hatching_kernels.glsl)
  HatchingRasterSettings raster{};    // how its strokes are drawn (hatching_quad.glsl)
  const gl::Texture* xtoon_image = nullptr;
  bool depth_pass = true;             // discs into depth first, the strokes tested against them
  SplatSettings discs;                // the depth pass's
  glm::vec4 paper{0.0f};
  int normal_k = 16;
  int spacing_k = 8;
  bool opacity_draws = false;         // a Gaussian splat's opacity scales its odds of strokes
  ColorSource color_source = ColorSource::Auto;
};

// What a capture of the marks reports of a point's strokes.
inline CapturedMark captured(const Stroke& s) {
  CapturedMark m;
  m.point_id = s.point_id;
  m.center = glm::vec3(s.center_alpha);
  m.direction = glm::vec3(s.d1_length);
  m.normal = glm::vec3(s.n_width);
  m.crossed = s.n_width.w < 0.0f;
  m.length = s.d1_length.w;
  m.color = glm::vec4(s.color, s.center_alpha.w);
  return m;
}

// The depth pass, the select and stroke passes and the resolve on the
// CPU's threads, from the same kernels as the GL passes.
void draw_strokes_native(const MarkContext& ctx, const ParamValues& p, const StrokePass& pass);

}  // namespace pointnpr::hatching
