// XDoG edges (cpp/filters/xdog.cpp), three passes.
// PASS_BLUR_X / PASS_BLUR_Y: separable covered-only sums
//   A = (sum L*c, sum c) at sigma, then at k sigma;  B = (sum c at sigma_fill)
// PASS_COMPOSE: XDoG soft threshold on covered pixels, silhouette outside.
// FDoG (flow_length > 0), between them: PASS_LIGHTNESS (L*c, c); the
// structure tensor's edge direction (kuwahara.comp's passes);
// PASS_FDOG_ACROSS: the DoG (1+p) G_sigma - p G_1.6sigma along the gradient
// direction (across the edges), (u, c); PASS_FDOG_ALONG: its Gaussian line
// integral along the flow curve through the pixel, (u, c).
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

#ifdef PASS_LIGHTNESS
layout(rgba32f, binding = 2) uniform writeonly image2D u_out_l;
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  imageStore(u_out_l, p, covered(c) ? vec4(lightness(c.rgb), 1.0, 0.0, 0.0) : vec4(0.0));
}
#endif

#if defined(PASS_FDOG_ACROSS) || defined(PASS_FDOG_ALONG)
layout(rgba32f, binding = 2) uniform writeonly image2D u_out_f;
layout(rgba32f, binding = 4) uniform readonly image2D u_src;   // (value, coverage) per pixel
#include "flow_curve.glsl"
uniform ivec2 u_valid_min;  // u_src is valid in [u_valid_min, u_valid_max)
uniform ivec2 u_valid_max;
uniform float u_p;
uniform float u_flow_sigma;

// (value * coverage, coverage) of u_src, bilinear at offset o from the
// centre of pixel p. Positions stay relative to the pixel (small numbers),
// so a tile, whose pixels are the frame's shifted, rounds them alike.
vec2 sample_src(ivec2 p, vec2 o) {
  vec2 fo = floor(o);
  ivec2 base = p + ivec2(fo);
  vec2 t = o - fo;
  vec2 acc = vec2(0.0);
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      ivec2 q = base + ivec2(i, j);
      if (any(lessThan(q, u_valid_min)) || any(greaterThanEqual(q, u_valid_max))) continue;
      vec2 v = imageLoad(u_src, q).xy;
      acc += (i == 1 ? t.x : 1.0 - t.x) * (j == 1 ? t.y : 1.0 - t.y) * vec2(v.x * v.y, v.y);
    }
  return acc;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  if (!covered(imageLoad(u_in, p))) {
    imageStore(u_out_f, p, vec4(0.0));
    return;
  }
#ifdef PASS_FDOG_ACROSS
  vec2 t = flow_tangent(p, vec2(0.0));
  vec2 n = vec2(t.y, -t.x);  // the gradient direction
  float sr = 1.6 * u_sigma;
  vec4 a = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    vec2 v = sample_src(p, float(k) * n);
    float d2 = float(k * k);
    a += vec4(gauss(d2, u_sigma) * v, gauss(d2, sr) * v);
  }
  float g1 = a.y > 0.0 ? a.x / a.y : 0.0;
  float g2 = a.w > 0.0 ? a.z / a.w : g1;
  imageStore(u_out_f, p, vec4((1.0 + u_p) * g1 - u_p * g2, 1.0, 0.0, 0.0));
#else
  // Both ways along the flow curve, one pixel per step.
  vec2 acc = sample_src(p, vec2(0.0));
  for (int side = -1; side <= 1; side += 2) {
    vec2 o = vec2(0.0), dir = float(side) * flow_tangent(p, o);
    for (int k = 1; k <= u_radius; ++k) {
      flow_step(p, o, dir);
      acc += gauss(float(k * k), u_flow_sigma) * sample_src(p, o);
    }
  }
  imageStore(u_out_f, p, vec4(acc.y > 0.0 ? acc.x / acc.y : 0.0, 1.0, 0.0, 0.0));
#endif
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
uniform int u_flow;  // FDoG: the response comes from u_fdog
layout(rgba32f, binding = 6) uniform readonly image2D u_fdog;

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
    float u = u_flow != 0 ? imageLoad(u_fdog, p).x : (1.0 + u_p) * g1 - u_p * g2;
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
