// brush_splats blending (a): two-pass Gaussian blur of the colour with
// depth occlusion: a neighbour counts only where its depth is within
// u_depth_tolerance (a fraction of the depth) of the pixel's, weighted by
// its coverage. Coverage (alpha) and depth stay as they are.
// PASS_X: sums (rgb a g, a g) along x into u_sums; PASS_Y: along y, divides.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_color_in;
layout(r32f, binding = 1) uniform readonly image2D u_depth;
#ifdef PASS_X
layout(rgba32f, binding = 2) uniform writeonly image2D u_sums;
#else
layout(rgba32f, binding = 2) uniform readonly image2D u_sums;
layout(rgba32f, binding = 3) uniform writeonly image2D u_color_out;
#endif
uniform float u_sigma;
uniform int u_radius;
uniform float u_depth_tolerance;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  float d = imageLoad(u_depth, p).r;
#ifdef PASS_X
  vec4 sum = vec4(0.0);
  if (!isinf(d)) {
    for (int k = -u_radius; k <= u_radius; ++k) {
      ivec2 q = ivec2(clamp(p.x + k, u_rect_min.x, u_rect_max.x - 1), p.y);
      float dq = imageLoad(u_depth, q).r;
      if (isinf(dq) || abs(dq - d) > u_depth_tolerance * d) continue;
      vec4 c = imageLoad(u_color_in, q);
      float w = exp(-0.5 * float(k * k) / (u_sigma * u_sigma)) * c.a;
      sum += vec4(c.rgb * w, w);
    }
  }
  imageStore(u_sums, p, sum);
#else
  vec4 c = imageLoad(u_color_in, p);
  if (isinf(d)) {
    imageStore(u_color_out, p, c);
    return;
  }
  vec4 sum = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = ivec2(p.x, clamp(p.y + k, u_rect_min.y, u_rect_max.y - 1));
    float dq = imageLoad(u_depth, q).r;
    if (isinf(dq) || abs(dq - d) > u_depth_tolerance * d) continue;
    sum += exp(-0.5 * float(k * k) / (u_sigma * u_sigma)) * imageLoad(u_sums, q);
  }
  imageStore(u_color_out, p, vec4(sum.a > 0.0 ? sum.rgb / sum.a : c.rgb, c.a));
#endif
}
