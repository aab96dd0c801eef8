// Coverage-normalized separable Gaussian (cpp/filters/blur.cpp).
// PASS_X: sums (rgb*a*g, a*g) along x into the scratch image.
// PASS_Y: sums those along y and divides, on covered pixels only.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
#ifdef PASS_X
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
#else
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(rgba32f, binding = 2) uniform readonly image2D u_sums;
#endif
uniform float u_sigma;
uniform int u_radius;

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
    float w = gauss(float(k * k), u_sigma) * clamp(c.a, 0.0, 1.0);
    s += vec4(c.rgb * w, w);
  }
  imageStore(u_out, p, s);
#else
  vec4 c = imageLoad(u_in, p);
  if (covered(c)) {
    vec4 s = vec4(0.0);
    for (int k = -u_radius; k <= u_radius; ++k) {
      ivec2 q = p + ivec2(0, k);
      if (!in_image(q, size)) continue;
      s += gauss(float(k * k), u_sigma) * imageLoad(u_sums, q);
    }
    if (s.a > 0.0) c.rgb = s.rgb / s.a;
  }
  imageStore(u_out, p, c);
#endif
}
