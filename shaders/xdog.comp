// XDoG edges (cpp/filters/xdog.cpp), three passes.
// PASS_BLUR_X / PASS_BLUR_Y: separable covered-only sums
//   A = (sum L*c, sum c) at sigma, then at k sigma;  B = (sum c at sigma_fill)
// PASS_COMPOSE: XDoG soft threshold on covered pixels, silhouette outside.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
uniform float u_sigma;
uniform float u_fill_sigma;
uniform int u_radius;

#if defined(PASS_BLUR_X) || defined(PASS_BLUR_Y)
layout(rgba32f, binding = 2) uniform writeonly image2D u_out_a;
layout(rgba32f, binding = 3) uniform writeonly image2D u_out_b;
layout(rgba32f, binding = 4) uniform readonly image2D u_in_a;
layout(rgba32f, binding = 5) uniform readonly image2D u_in_b;
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
#ifdef PASS_BLUR_X
  const ivec2 axis = ivec2(1, 0);
#else
  const ivec2 axis = ivec2(0, 1);
#endif
  float sr = 1.6 * u_sigma, sf = max(u_fill_sigma, 1e-3);
  vec4 a = vec4(0.0), b = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = p + k * axis;
    if (!in_image(q, size)) continue;
#ifdef PASS_BLUR_X
    vec4 c = imageLoad(u_in, q);
    float cov = covered(c) ? 1.0 : 0.0;
    float L = cov > 0.0 ? lightness(c.rgb) : 0.0;
    vec4 va = vec4(L * cov, cov, L * cov, cov);
    vec4 vb = vec4(cov, 0.0, 0.0, 0.0);
#else
    vec4 va = imageLoad(u_in_a, q);
    vec4 vb = imageLoad(u_in_b, q);
#endif
    float d2 = float(k * k);
    float ke = gauss(d2, u_sigma), kr = gauss(d2, sr), kf = gauss(d2, sf);
    a += vec4(ke, ke, kr, kr) * va;
    b += vec4(kf, 0.0, 0.0, 0.0) * vb;
  }
  imageStore(u_out_a, p, a);
  imageStore(u_out_b, p, b);
}
#endif

#ifdef PASS_COMPOSE
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(rgba32f, binding = 4) uniform readonly image2D u_sums_a;
layout(rgba32f, binding = 5) uniform readonly image2D u_sums_b;
uniform float u_p;
uniform float u_epsilon;
uniform float u_phi;
uniform float u_thickness;
uniform int u_outline;
uniform int u_lines_only;
uniform float u_fill_norm;
uniform vec4 u_edge_color;

// A covered pixel with 40 % of its neighbourhood covered, or a hole with
// half of it covered, is surface; lone splats (a 3x3 splat covers 30 % at
// the default fill_gaps) are not.
bool solid(ivec2 q) {
  if (!in_image(q, imageSize(u_in))) return false;
  bool cov = covered(imageLoad(u_in, q));
  if (u_fill_norm <= 0.0) return cov;
  float frac = imageLoad(u_sums_b, q).x / u_fill_norm;
  return cov ? frac >= 0.4 : frac >= 0.5;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (covered(c)) {
    vec4 a = imageLoad(u_sums_a, p);
    float g1 = a.y > 0.0 ? a.x / a.y : 0.0;
    float g2 = a.w > 0.0 ? a.z / a.w : g1;
    float u = (1.0 + u_p) * g1 - u_p * g2;
    float ink = u >= u_epsilon ? 0.0 : -tanh(u_phi * (u - u_epsilon));
    ink *= u_edge_color.a;
    if (u_lines_only != 0) {
      imageStore(u_out, p, ink > 0.0 ? vec4(u_edge_color.rgb, ink) : vec4(0.0));
    } else {
      imageStore(u_out, p, vec4(mix(c.rgb, u_edge_color.rgb, ink), c.a));
    }
    return;
  }
  // Background or hole: the silhouette, antialiased, where a solid pixel is
  // within `thickness` and this pixel is not surface itself.
  if (u_outline > 0 && !solid(p)) {
    float nearest = 1e9;
    int w = u_outline;
    for (int dy = -w; dy <= w; ++dy)
      for (int dx = -w; dx <= w; ++dx) {
        float d = length(vec2(dx, dy));
        if (d < nearest && d <= float(w) + 0.5 && solid(p + ivec2(dx, dy))) nearest = d;
      }
    float alpha = clamp(u_thickness + 0.5 - nearest, 0.0, 1.0) * u_edge_color.a;
    if (alpha > 0.0) {
      imageStore(u_out, p, vec4(u_edge_color.rgb, alpha));
      return;
    }
  }
  imageStore(u_out, p, c);
}
#endif
