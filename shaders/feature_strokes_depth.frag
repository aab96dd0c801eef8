// Feature strokes, pass 1: opaque discs; linear depth of the surface (not
// the pushed one) for the resolve and the compositing.
flat in float v_depth;
flat in float v_diameter;
flat in vec2 v_center;
flat in vec3 v_shape;
#include "feature_strokes_disc.glsl"
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_depth;

void main() {
  // From the pixel centre, not gl_PointCoord (interpolated from the images'
  // corner, so its rounding would move with a tile's origin).
  vec2 offset = gl_FragCoord.xy - v_center;
  if (v_diameter >= 2.0 && !on_disc(offset, v_diameter, v_shape)) discard;
  o_color = vec4(0.0);
  o_depth = v_depth;
}
