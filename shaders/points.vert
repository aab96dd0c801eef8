// Conventional GL_POINTS path: the reference and benchmark baseline.
// Reversed-Z (glClipControl 0..1, GL_GREATER) keeps depth precise far away;
// linear depth is written to a colour attachment for compositing.
#include "points.glsl"
// Tiles (cpp/render/exact_raster.h): the frame pixel on a 1/256 grid, less
// the tile's origin, placed where a power-of-two viewport's transform is
// exact: the rasterizer sees the same subpixel centre in every tile, so
// coverage is the frame's.
#include "exact_window.glsl"

flat out vec4 v_color;
flat out float v_depth;
flat out float v_diameter;
flat out vec2 v_center;  // window position in the images (pixels)
flat out float v_spacing;

void main() {
  uint index = uint(gl_VertexID);
  Splat s = project_point(index);
  v_color = point_color(index);
  v_depth = s.depth;
  v_diameter = s.diameter;
  v_spacing = point_spacing(index);
  gl_PointSize = s.diameter;
  if (!s.visible) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume
    return;
  }
  vec2 win = exact_window(s.center);
  v_center = win;
  float z = u_ortho != 0 ? 1.0 - (s.depth - u_near) / (u_far - u_near) : u_near / s.depth;
  gl_Position = exact_clip(win, z);
}
