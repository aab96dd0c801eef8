// The gaussians mark's frame settings, declared once for both backends
// (the subset: cpp/core/glsl.h).
#ifndef GAUSSIANS_SETTINGS_GLSL
#define GAUSSIANS_SETTINGS_GLSL
SETTINGS_BLOCK(GaussianSettings, 0)
  vec4 proj_row0;  // the projection's rows 0, 1 and 3 (clip x, y, w from view space)
  vec4 proj_row1;
  vec4 proj_row3;
  vec4 frame;      // the frame's width, height; the tile's origin x, y
  vec4 near_far;   // clip start, clip end
  int ortho;
  float dilation;  // added to the 2D covariance's diagonal (px^2)
  float max_radius;
  int sh_degree;
END_SETTINGS_BLOCK(u)
#endif
