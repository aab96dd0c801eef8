// Shared by the hatching mark's passes (cpp/marks/hatching.cpp).
#include "id_hash.glsl"
struct Stroke {
  vec4 center_alpha;  // view-space centre, opacity (<= 0: no stroke)
  vec4 d1_length;     // unit direction of the first line, length (scene units)
  vec4 n_width;       // unit normal, width (scene units; negative: crossed)
  vec3 color;         // display sRGB
  uint point_id;
};
layout(std430, binding = 7) buffer Strokes { Stroke strokes[]; };

