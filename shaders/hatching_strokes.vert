// Hatching, pass 2: 12 vertices per point record, two quads (the second
// only for crossing strokes); records without a stroke make no triangle.
// The quads and their pixels: hatching_quad.glsl, shared with the native
// backend.
#include "hatching_common.glsl"
#include "shared_kernels.glsl"
#include "hatching_quad.glsl"
#include "exact_window.glsl"

flat out StrokeQuad v_quad;

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  uint record = uint(gl_VertexID) / 12u;
  uint line = (uint(gl_VertexID) % 12u) / 6u;
  StrokeQuad q = stroke_quad(strokes[record], line);
  if (!(q.size.x > 0.0)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: no triangle
    return;
  }
  gl_Position = exact_clip(exact_window(quad_corner(q, CORNERS[uint(gl_VertexID) % 6u])), 0.5);
  v_quad = q;
}
