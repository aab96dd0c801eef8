// brush_splats: the blended splats into the segment's colour (straight
// alpha = coverage 1 - transmittance) and depth (the nearest brush surface,
// else the splats' own where only they reached).
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform writeonly image2D u_color;
layout(r32f, binding = 1) uniform image2D u_depth;   // in: the depth pass; out: the segment's depth
layout(rgba32f, binding = 2) uniform readonly image2D u_accum;
layout(r32f, binding = 3) uniform readonly image2D u_reveal;
layout(r32f, binding = 4) uniform readonly image2D u_splat_depth;

void main() {
  ivec2 q;
  if (!rect_pixel(q)) return;
  float alpha = 1.0 - clamp(imageLoad(u_reveal, q).r, 0.0, 1.0);
  vec4 acc = imageLoad(u_accum, q);
  if (alpha > 0.0 && acc.a > 0.0) {
    float surface = imageLoad(u_depth, q).r;
    imageStore(u_color, q, vec4(clamp(acc.rgb / acc.a, 0.0, 1.0), alpha));
    imageStore(u_depth, q, vec4(isinf(surface) ? imageLoad(u_splat_depth, q).r : surface));
  } else {
    imageStore(u_color, q, vec4(0.0));
    imageStore(u_depth, q, vec4(INF));
  }
}
