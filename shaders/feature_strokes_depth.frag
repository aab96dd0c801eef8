// Feature strokes, pass 1: opaque discs; linear depth of the surface (not
// the pushed one) for the resolve and the compositing.
flat in float v_depth;
flat in float v_diameter;
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_depth;

void main() {
  vec2 offset = (gl_PointCoord - 0.5) * v_diameter;
  if (v_diameter >= 2.0 && dot(offset, offset) > 0.25 * v_diameter * v_diameter) discard;
  o_color = vec4(0.0);
  o_depth = v_depth;
}
