// The hatching mark's stroke settings: one block both backends read
// (cpp/marks/hatching/settings.h; the subset: cpp/core/glsl.h).
#ifndef HATCHING_SETTINGS_GLSL
#define HATCHING_SETTINGS_GLSL
SETTINGS_BLOCK(HatchingSettings, 0)
  vec4 light_dir;       // towards the light, view space (xyz)
  vec4 direction;       // line direction u, view space (xyz)
  vec4 constant_color;  // the stroke colour (display sRGB)
  vec4 pencils[64];     // rgb, hue; sorted by hue
  int ortho;
  float near_plane;
  float far_plane;
  float depth_min;
  float depth_max;
  float px_per_unit;
  float ambient;
  float specular;
  int two_sided;
  float shininess;
  int xtoon;            // pencil, wax_crayon, two_colored, chalk, ink, image
  float density;
  float cross_share;
  float coverage;       // 0: off
  int world_units;
  float stroke_length;
  float stroke_width;
  float length_jitter;
  float curvature_length;
  float position_jitter;
  float angle_jitter;   // radians
  int coloring;         // constant, xtoon, point
  float point_blend;
  float hue_shift;      // turns
  int pencil_count;
  float opacity;
  float alpha_modification;
  float alpha_jitter;
  uint seed;
END_SETTINGS_BLOCK(u)
#endif
