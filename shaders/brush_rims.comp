// brush_splats: rims over the surface behind (brush_rims.glsl), from the
// resolved colour and depth into u_out over the mark's clip.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_color;
layout(r32f, binding = 1) uniform readonly image2D u_depth;
layout(rgba32f, binding = 2) uniform writeonly image2D u_out;
layout(r32f, binding = 3) uniform readonly image2D u_offset;  // the surface's splat's blend offset
uniform vec2 u_footprint;
uniform float u_grazing;
uniform int u_reach;
uniform ivec2 u_clip_min;
uniform ivec2 u_clip_max;

vec4 rim_color(ivec2 p) { return imageLoad(u_color, p); }
float rim_depth(ivec2 p) { return imageLoad(u_depth, p).r; }
float rim_offset(ivec2 p) { return imageLoad(u_offset, p).r; }
bool rim_in(ivec2 p) { return all(greaterThanEqual(p, u_clip_min)) && all(lessThan(p, u_clip_max)); }
#include "brush_rims.glsl"

void main() {
  ivec2 q;
  if (!rect_pixel(q)) return;
  imageStore(u_out, q, rim_fill(q, RimRule(u_footprint.x, u_footprint.y, u_grazing, u_reach)));
}
