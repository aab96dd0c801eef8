// Shared by the feature_strokes mark's passes (cpp/marks/feature_strokes.cpp).
#include "id_hash.glsl"
struct Record {
  vec4 center_kind;  // view-space centre, class (0 directional, 1 non-directional, 2 dithering)
  vec4 dir_length;   // view-space unit 3D direction (directional) or 0, length (px)
  vec4 color;        // display sRGB, opacity
  uint point_id;
  uint primitive;    // 1 point sprite, 2 line segment, 3 textured stroke
  float width;       // px
  float pad;
};
layout(std430, binding = 7) buffer Records { Record records[]; };

