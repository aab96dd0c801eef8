// The stipples mark's settings, declared once for both backends
// (cpp/marks/stipples/settings.h; the subset: cpp/core/glsl.h): what is
// fixed for a frame (u) and the window of the frame the hidden-point passes
// run over (win). Each is one uniform block on GL.
#ifndef STIPPLES_SETTINGS_GLSL
#define STIPPLES_SETTINGS_GLSL
SETTINGS_BLOCK(StippleSettings, 0)
  mat4 projection;    // the camera's, to the frame's pixels
  vec4 light_dir;     // orthographic light, towards it, view space (xyz)
  vec4 light_right;
  vec4 light_up;
  vec4 dot_color;
  vec4 paper;
  ivec2 frame_px;     // the whole frame's size (the projection maps to it)
  ivec2 origin_px;    // the tile's corner in the frame
  ivec2 clip_min;     // the tile's pixels the mark draws (local)
  ivec2 clip_max;
  vec2 light_origin;  // (right, up) of the light texture's corner
  float near_plane;
  float far_plane;
  int ortho;
  float px_per_unit;  // pixels per scene unit at view depth 1
  float factor;       // fine texels per pixel
  float offset;       // depth added per spreading step, scene units
  int casters_all;    // 1: every point casts into the light quadtree, 0: visible points only
  float light_extent; // side of the light texture, scene units
  int levels;         // n: the quadtree's finest level is 2^n x 2^n
  int diffuse;
  int level_lo;
  float level_frac;
  int specular;
  float tau;
  float eye_cell;     // pixels
  int light_cells;    // per side
  float dot_size;
  float size_jitter;
  uint seed;
  int capture;
  int level_from_spacing;  // 1: each point's level from its spacing (lit_scale's cell_target)
  float tone_scale;   // dot_size dots wanted per pixel of surface (-ln(1 - tone) / dot area); 0: off
  int lit_share;      // 1: lit points hidden by the share of N.L (lit_scale), 0: the cell's nearest (the paper's)
  float share_scale;  // lit_scale's share per unit of N.L
  int quadtree;       // 1: the light-view quadtree is built (nearest, or share with cast shadows)
  int spread_max;     // spread_from_spacing: the most fine texels a point covers each way (spread_texels); 0: off
END_SETTINGS_BLOCK(u)

// A piece of the frame: its fine texture (frame texels [fine_min,
// fine_min + fine_size)), its eye cells, and the fine texels whose points it
// counts for the frame (each point in exactly one window's).
SETTINGS_BLOCK(StippleWindowSettings, 1)
  ivec2 fine_min;
  ivec2 fine_size;
  ivec2 owned_min;
  ivec2 owned_max;
  ivec2 eye_min;
  ivec2 eye_cells;
END_SETTINGS_BLOCK(win)
#endif
