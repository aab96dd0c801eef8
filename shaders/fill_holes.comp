// Hole filling (cpp/filters/fill_holes.cpp): separable Gaussian sums of
// (rgb*c, c); a hole enclosed by points (on both sides of at least
// u_axes of the 4 lines through it, within u_reach) takes their mean.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(rgba32f, binding = 2) uniform readonly image2D u_sums;
uniform float u_sigma;
uniform int u_radius;
uniform int u_reach;
uniform int u_axes;

// Distance to the first covered pixel along d, within u_reach.
bool hits(ivec2 p, ivec2 d, ivec2 size) {
  for (int k = 1; k <= u_reach; ++k) {
    ivec2 q = p + k * d;
    if (!in_image(q, size)) return false;
    if (covered(imageLoad(u_in, q))) return true;
  }
  return false;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
#ifdef PASS_X
  vec4 s = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = p + ivec2(k, 0);
    if (!in_image(q, size)) continue;
    vec4 c = imageLoad(u_in, q);
    float w = covered(c) ? gauss(float(k * k), u_sigma) : 0.0;
    s += vec4(c.rgb * w, w);
  }
  imageStore(u_out, p, s);
#else
  vec4 c = imageLoad(u_in, p);
  const ivec2 dirs[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1));
  int enclosed = 0;
  if (!covered(c))
    for (int i = 0; i < 4; ++i) enclosed += hits(p, dirs[i], size) && hits(p, -dirs[i], size) ? 1 : 0;
  if (enclosed >= u_axes) {
    vec4 s = vec4(0.0);
    for (int k = -u_radius; k <= u_radius; ++k) {
      ivec2 q = p + ivec2(0, k);
      if (in_image(q, size)) s += gauss(float(k * k), u_sigma) * imageLoad(u_sums, q);
    }
    if (s.a > 0.0) c = vec4(s.rgb / s.a, 1.0);
  }
  imageStore(u_out, p, c);
#endif
}
