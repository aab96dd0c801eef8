// The hatching mark's settings and records, declared once for both
// backends (cpp/marks/hatching/settings.h; the subset: cpp/core/glsl.h):
// the select pass's settings (u), the strokes it hands on (Stroke, std430),
// the stroke pass's settings (raster) and a line of a stroke (StrokeQuad).
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
  float color_tone;     // 0 unless coloring is point
  float hue_shift;      // turns
  int pencil_count;
  float opacity;
  float alpha_modification;
  float alpha_jitter;
  uint seed;
  int grow_sparse;      // 1: strokes too sparse for the coverage grow (grow_sparse_strokes)
END_SETTINGS_BLOCK(u)

// A point's strokes (std430, 64 bytes).
struct Stroke {
  vec4 center_alpha;  // view-space centre, opacity (<= 0: no stroke)
  vec4 d1_length;     // unit direction of the first line, length (scene units)
  vec4 n_width;       // unit normal, width (scene units; negative: crossed)
  vec3 color;         // display sRGB
  uint point_id;
};

SETTINGS_BLOCK(HatchingRasterSettings, 1)
  mat4 projection;
  mat4 inv_projection;
  int size_x;              // the frame's (the projection maps to it)
  int size_y;
  int ortho;
  float near_plane;
  float far_plane;
  float px_per_unit;
  float offset_radii;      // move toward the camera by this many depth-disc radii
  int disc_world;          // 1: disc_size in scene units, 0: in pixels
  float disc_size;         // depth-disc diameter
  float max_reach;         // pixels from the centre a stroke may reach (its tiles' halo)
  int stroke_texture;      // pencil, crayon, ink, soft
  int clip_to_surface;
END_SETTINGS_BLOCK(raster)

// One line of a point's strokes, as its pixels see it.
struct StrokeQuad {
  vec4 color;      // display sRGB, alpha = opacity
  vec3 center;     // view space
  float aspect;    // length / width
  vec3 along;      // unit, the line
  float offset;    // toward the camera (scene units)
  vec3 across;     // unit, across it
  uint id;         // the point's id x 2 + the line
  vec2 size;       // length, width (scene units); 0: no quad
  vec2 center_px;  // the centre's frame pixel
};

#endif
