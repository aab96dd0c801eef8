// Conventional GL_POINTS path: the reference and benchmark baseline.
// Reversed-Z (glClipControl 0..1, GL_GREATER) keeps depth precise far away;
// linear depth is written to a colour attachment for compositing.
#include "points.glsl"

flat out vec4 v_color;
flat out float v_depth;
flat out float v_diameter;

void main() {
  uint index = uint(gl_VertexID);
  Splat s = project_point(index);
  v_color = point_color(index);
  v_depth = s.depth;
  v_diameter = s.diameter;
  gl_PointSize = s.diameter;
  if (!s.visible) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume
    return;
  }
  vec2 ndc = s.center / vec2(u_size) * 2.0 - 1.0;
  float z = u_ortho != 0 ? 1.0 - (s.depth - u_near) / (u_far - u_near) : u_near / s.depth;
  gl_Position = vec4(ndc, z, 1.0);
}
