// The feature_strokes mark's settings and records, declared once for both
// backends (cpp/marks/feature_strokes/feature_strokes.h; the subset:
// cpp/core/glsl.h): the settings its select and stroke passes read (one
// uniform block), the record a point hands on (std430) and a record as its
// pixels see it.
#ifndef FEATURE_STROKES_SETTINGS_GLSL
#define FEATURE_STROKES_SETTINGS_GLSL
SETTINGS_BLOCK(FeatureStrokesSettings, 0)
  mat4 projection;
  vec4 constant_color;       // the stroke colour (display sRGB)
  vec4 light_dir;            // towards the light, view space (xyz; shading)
  int size_x;                // the frame's (the projection maps to it)
  int size_y;
  int ortho;
  float near_plane;
  float far_plane;
  float threshold;           // feature degree above which a point is a feature
  float line_error;
  int use_lines;
  float dither;
  float dither_tone;
  int prim_directional;      // per class: 0 none, 1 sprite, 2 line, 3 textured stroke
  int prim_other;
  int prim_dither;
  float directional_length;  // px
  float other_length;
  float sprite_size;
  float stroke_width;
  float line_width;
  int point_coloring;
  float opacity;
  uint seed;
  float screen_dir_x;        // unit, pixels (x right, y up)
  float screen_dir_y;
  int stroke_texture;        // taper, brush, dry, image
  float shading_strength;
  float tone;                // 0: the paper's dithering odds; else the dithering's ink (marks' area per surface)
  float px_per_unit;         // pixels per scene unit at view depth 1 (orthographic: at any depth)
  float dither_area;         // px^2 of one dithering primitive
  float other_area;          // px^2 of one non-directional primitive
  float line_tone;           // how much the light thins feature primitives (their width)
  int chain_lines;           // chained directional points draw their links (chain_lines where it applies)
END_SETTINGS_BLOCK(u)

struct Record {
  vec4 center_kind;  // view-space centre, class (0 directional, 1 non-directional, 2 dithering)
  vec4 dir_length;   // view-space unit 3D direction (directional) or 0, length (px)
  vec4 color;        // display sRGB, opacity
  uint point_id;
  uint primitive;    // 0 none, 1 point sprite, 2 line segment, 3 textured stroke
  float width;       // px
  float chain;       // 0: a point's own stroke; else the link to its parent, 1 + its free ends (bit 0 the
                     // point's, bit 1 the parent's: geometry/feature_chains.h)
};

// A record's screen-aligned quad (seed 001 Fig. 5).
struct StrokeSprite {
  vec4 color;      // display sRGB, opacity
  vec2 center;     // frame pixels
  vec2 r1;         // unit, along the stroke (r2 = r1 turned 90 degrees)
  vec2 size;       // length, width (pixels)
  float depth;     // linear
  float z;         // reversed Z, for the depth test
  float aspect;    // length / width
  uint primitive;
  uint id;
  float chain;     // Record::chain
};
#endif
