// Cartoon filter (see cpp/filters/cartoon.cpp), three passes.
// Gaussian means over covered pixels only are normalized convolutions,
// which are separable: blur (L*a, a) and (rgb*a) horizontally, then
// vertically, then divide. Background never produces edges that way.
// PASS_BLUR_X / PASS_BLUR_Y write two images:
//   A = (sum L*a at sigma_e, sum a at sigma_e, sum L*a at 1.6 sigma_e, sum a at 1.6 sigma_e)
//   B = (sum rgb*a at sigma_e, sum a at sigma_fill)
// PASS_COMPOSE: quantize, darken DoG edges, fill gaps, draw outlines.
// PASS_BILATERAL (before them, iterated): one axis of a separable bilateral
//   filter in CIELAB over covered pixels; images in between hold (Lab, a).
//   With radius 0 and sRGB input it only converts to CIELAB.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
uniform float u_sigma;
uniform int u_radius;
uniform float u_fill_sigma;

#ifdef PASS_BILATERAL
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform ivec2 u_axis;
uniform int u_in_srgb;   // the input is display sRGB (first pass), else Lab
uniform int u_out_srgb;  // write display sRGB (last pass), else Lab
uniform float u_space_sigma;
uniform float u_range_sigma;
uniform int u_bilateral_radius;

vec4 fetch_lab(ivec2 q) {
  if (!in_image(q, imageSize(u_in))) return vec4(0.0);
  vec4 c = imageLoad(u_in, q);
  if (!covered(c)) return vec4(0.0);
  return u_in_srgb != 0 ? vec4(srgb_to_lab(c.rgb), c.a) : c;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 centre = fetch_lab(p);
  if (!covered(centre)) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  float inv_range = 1.0 / (2.0 * u_range_sigma * u_range_sigma);
  vec4 sum = vec4(0.0);
  for (int k = -u_bilateral_radius; k <= u_bilateral_radius; ++k) {
    vec4 c = fetch_lab(p + k * u_axis);
    if (!covered(c)) continue;
    vec3 d = c.rgb - centre.rgb;
    float w = gauss(float(k * k), u_space_sigma) * exp(-dot(d, d) * inv_range);
    sum += vec4(c.rgb * w, w);
  }
  vec3 lab = sum.rgb / sum.w;
  imageStore(u_out, p, vec4(u_out_srgb != 0 ? lab_to_srgb(lab) : lab, centre.a));
}
#endif

#if defined(PASS_BLUR_X) || defined(PASS_BLUR_Y)
#ifdef PASS_BLUR_X
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
const ivec2 AXIS = ivec2(1, 0);
#else
layout(rgba32f, binding = 4) uniform readonly image2D u_in_a;
layout(rgba32f, binding = 5) uniform readonly image2D u_in_b;
const ivec2 AXIS = ivec2(0, 1);
#endif
layout(rgba32f, binding = 2) uniform writeonly image2D u_out_a;
layout(rgba32f, binding = 3) uniform writeonly image2D u_out_b;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  float se = u_sigma, sr = 1.6 * u_sigma, sf = max(u_fill_sigma, 1e-3);
  vec4 a = vec4(0.0), b = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = p + k * AXIS;
#ifdef PASS_BLUR_X
    ivec2 size = imageSize(u_in);
    if (!in_image(q, size)) continue;
    vec4 c = imageLoad(u_in, q);
    float cov = c.a > 0.0 ? 1.0 : 0.0;
    vec4 va = vec4(luminance(c.rgb) * cov, cov, luminance(c.rgb) * cov, cov);
    vec4 vb = vec4(c.rgb * cov, cov);
#else
    ivec2 size = imageSize(u_in_a);
    if (!in_image(q, size)) continue;
    vec4 va = imageLoad(u_in_a, q);
    vec4 vb = imageLoad(u_in_b, q);
#endif
    float d2 = float(k * k);
    float ke = exp(-d2 / (2.0 * se * se));
    float kr = exp(-d2 / (2.0 * sr * sr));
    float kf = exp(-d2 / (2.0 * sf * sf));
    a += vec4(ke, ke, kr, kr) * va;
    b += vec4(ke, ke, ke, kf) * vb;
  }
  imageStore(u_out_a, p, a);
  imageStore(u_out_b, p, b);
}
#endif

#ifdef PASS_COMPOSE
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(rgba32f, binding = 4) uniform readonly image2D u_sums_a;
layout(rgba32f, binding = 5) uniform readonly image2D u_sums_b;
uniform int u_levels;
uniform float u_sharpness;
uniform float u_edge_sensitivity;
uniform float u_edge_strength;
uniform int u_outline_width;
uniform vec4 u_edge_color;
uniform float u_fill_norm;  // total weight of the 2D fill kernel

// Fraction of the fill kernel around q that is covered.
float coverage(ivec2 q) {
  if (!in_image(q, imageSize(u_in))) return 0.0;
  return imageLoad(u_sums_b, q).a / u_fill_norm;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  vec4 a = imageLoad(u_sums_a, p);
  vec4 b = imageLoad(u_sums_b, p);
  // A hole counts as surface when a third of its neighbourhood is covered
  // (so interior holes are filled, not outlined); only half-covered
  // neighbourhoods cast outlines, so lone points do not sprout rings.
  bool filled = c.a <= 0.0 && u_fill_norm > 0.0 && coverage(p) >= 0.3 && a.y > 0.0;
  if (c.a > 0.0 || filled) {
    vec3 base = c.a > 0.0 ? c.rgb : b.rgb / a.y;
    float L = luminance(base);
    float step_size = 1.0 / float(u_levels - 1);
    float q = floor(L / step_size + 0.5) * step_size;
    float Lq = q + step_size * soft_step(u_sharpness, (L - q) / step_size);
    vec3 rgb = L < 1e-4 ? vec3(Lq) : clamp(base * (Lq / L), 0.0, 1.0);
    float le = a.y > 0.0 ? a.x / a.y : 0.0;
    float lr = a.w > 0.0 ? a.z / a.w : 0.0;
    float D = le - 0.98 * lr;
    float E = D > 0.0 ? 1.0 : 1.0 + tanh(u_edge_sensitivity * D);
    rgb = mix(rgb, u_edge_color.rgb, (1.0 - E) * u_edge_strength);
    imageStore(u_out, p, vec4(rgb, 1.0));
    return;
  }
  int w = u_outline_width;
  for (int dy = -w; dy <= w; ++dy)
    for (int dx = -w; dx <= w; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (dx * dx + dy * dy > w * w) continue;
      bool solid = u_fill_norm > 0.0 ? coverage(q) >= 0.5 : (in_image(q, imageSize(u_in)) && imageLoad(u_in, q).a > 0.0);
      if (solid) {
        imageStore(u_out, p, u_edge_color);
        return;
      }
    }
  imageStore(u_out, p, vec4(0.0));
}
#endif
