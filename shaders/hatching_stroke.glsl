// A point's strokes as the hatching mark's passes hand them on (std430, 64
// bytes; both backends: the subset of cpp/core/glsl.h).
#ifndef HATCHING_STROKE_GLSL
#define HATCHING_STROKE_GLSL
struct Stroke {
  vec4 center_alpha;  // view-space centre, opacity (<= 0: no stroke)
  vec4 d1_length;     // unit direction of the first line, length (scene units)
  vec4 n_width;       // unit normal, width (scene units; negative: crossed)
  vec3 color;         // display sRGB
  uint point_id;
};
#endif
