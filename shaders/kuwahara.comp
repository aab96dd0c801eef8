// Anisotropic Kuwahara filter (cpp/filters/kuwahara.cpp), four passes.
// PASS_TENSOR:   structure tensor (E, F, G, coverage) from Sobel derivatives
//                of covered pixels (uncovered neighbours mirror the centre).
// PASS_SMOOTH_X/Y: coverage-normalized Gaussian of the tensor; Y also turns
//                it into (edge direction t, anisotropy A, 1).
// PASS_FILTER:   elliptical 8-sector Kuwahara with polynomial weights.
// PASS_HEIGHT:   (impasto) paint height: noise smeared along the edge
//                direction plus thickness from lightness.
// PASS_SHADE:    (impasto) the height lit as a bump map.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform float u_sigma;
uniform int u_radius;

#ifdef PASS_TENSOR
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
  vec4 c0 = imageLoad(u_in, p);
  if (!covered(c0)) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  vec3 n[9];
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      ivec2 q = p + ivec2(i, j);
      vec4 c = in_image(q, size) ? imageLoad(u_in, q) : vec4(0.0);
      n[(j + 1) * 3 + (i + 1)] = covered(c) ? c.rgb : c0.rgb;
    }
  vec3 gx = (n[2] + 2.0 * n[5] + n[8] - n[0] - 2.0 * n[3] - n[6]) * 0.25;
  vec3 gy = (n[6] + 2.0 * n[7] + n[8] - n[0] - 2.0 * n[1] - n[2]) * 0.25;
  imageStore(u_out, p, vec4(dot(gx, gx), dot(gx, gy), dot(gy, gy), 1.0));
}
#endif

#if defined(PASS_SMOOTH_X) || defined(PASS_SMOOTH_Y)
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
#ifdef PASS_SMOOTH_X
  const ivec2 axis = ivec2(1, 0);
#else
  const ivec2 axis = ivec2(0, 1);
#endif
  vec4 s = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = p + k * axis;
    if (in_image(q, size)) s += gauss(float(k * k), u_sigma) * imageLoad(u_in, q);
  }
#ifdef PASS_SMOOTH_X
  imageStore(u_out, p, s);
#else
  vec3 g = s.w > 0.0 ? s.xyz / s.w : vec3(0.0);  // E, F, G
  float E = g.x, F = g.y, G = g.z;
  float root = sqrt(max((E - G) * (E - G) + 4.0 * F * F, 0.0));
  float l1 = 0.5 * (E + G + root), l2 = 0.5 * (E + G - root);
  vec2 v = vec2(l1 - E, -F);  // minor eigenvector: along the edge
  vec2 t = length(v) > 0.0 ? normalize(v) : vec2(0.0, 1.0);
  float A = l1 + l2 > 1e-12 ? (l1 - l2) / (l1 + l2) : 0.0;
  imageStore(u_out, p, vec4(t, A, 1.0));
#endif
}
#endif

#ifdef PASS_FILTER
layout(rgba32f, binding = 2) uniform readonly image2D u_tensor;
uniform float u_window;
uniform float u_alpha;
uniform float u_q;
uniform float u_zeta;
uniform float u_eta;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
  vec4 c0 = imageLoad(u_in, p);
  if (!covered(c0)) {
    imageStore(u_out, p, c0);
    return;
  }
  vec4 tf = imageLoad(u_tensor, p);
  vec2 t = tf.xy;
  float A = tf.z;
  float a = u_window * clamp((u_alpha + A) / u_alpha, 0.1, 2.0);
  float b = u_window * clamp(u_alpha / (u_alpha + A), 0.1, 2.0);
  int max_x = int(sqrt(a * a * t.x * t.x + b * b * t.y * t.y));
  int max_y = int(sqrt(a * a * t.y * t.y + b * b * t.x * t.x));
  vec4 m[8];
  vec3 s[8];
  for (int k = 0; k < 8; ++k) {
    m[k] = vec4(0.0);
    s[k] = vec3(0.0);
  }
  for (int j = -max_y; j <= max_y; ++j)
    for (int i = -max_x; i <= max_x; ++i) {
      vec2 d = vec2(i, j);
      // Offset in the ellipse's frame, scaled to a disc of radius 0.5.
      vec2 v = vec2(dot(d, t) * 0.5 / a, dot(d, vec2(-t.y, t.x)) * 0.5 / b);
      if (dot(v, v) > 0.25) continue;
      ivec2 q = p + ivec2(i, j);
      if (!in_image(q, size)) continue;
      vec4 c = imageLoad(u_in, q);
      if (!covered(c)) continue;
      float w[8];
      float sum = 0.0, z, vxx, vyy;
      vxx = u_zeta - u_eta * v.x * v.x;
      vyy = u_zeta - u_eta * v.y * v.y;
      z = max(0.0, v.y + vxx); w[0] = z * z; sum += w[0];
      z = max(0.0, -v.x + vyy); w[2] = z * z; sum += w[2];
      z = max(0.0, -v.y + vxx); w[4] = z * z; sum += w[4];
      z = max(0.0, v.x + vyy); w[6] = z * z; sum += w[6];
      vec2 r = 0.70710678 * vec2(v.x - v.y, v.x + v.y);
      vxx = u_zeta - u_eta * r.x * r.x;
      vyy = u_zeta - u_eta * r.y * r.y;
      z = max(0.0, r.y + vxx); w[1] = z * z; sum += w[1];
      z = max(0.0, -r.x + vyy); w[3] = z * z; sum += w[3];
      z = max(0.0, -r.y + vxx); w[5] = z * z; sum += w[5];
      z = max(0.0, r.x + vyy); w[7] = z * z; sum += w[7];
      if (sum <= 0.0) continue;
      float g = exp(-3.125 * dot(v, v)) / sum;
      for (int k = 0; k < 8; ++k) {
        float wk = w[k] * g;
        m[k] += vec4(c.rgb * wk, wk);
        s[k] += c.rgb * c.rgb * wk;
      }
    }
  vec4 o = vec4(0.0);
  for (int k = 0; k < 8; ++k) {
    if (m[k].w <= 0.0) continue;
    vec3 mean = m[k].rgb / m[k].w;
    vec3 var = abs(s[k] / m[k].w - mean * mean);
    float sigma2 = var.r + var.g + var.b;
    float w = 1.0 / (1.0 + pow(255.0 * sigma2, 0.5 * u_q));
    o += vec4(mean * w, w);
  }
  imageStore(u_out, p, vec4(o.w > 0.0 ? clamp(o.rgb / o.w, 0.0, 1.0) : c0.rgb, c0.a));
}
#endif

#ifdef PASS_HEIGHT
layout(rgba32f, binding = 2) uniform readonly image2D u_tensor;
uniform float u_brush_size;
uniform int u_stroke_length;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (!covered(c)) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  vec2 t = imageLoad(u_tensor, p).xy;
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  float sum = 0.0, wsum = 0.0;
  float sigma = 0.5 * float(u_stroke_length);
  for (int k = -u_stroke_length; k <= u_stroke_length; ++k) {
    float w = gauss(float(k * k), sigma);
    sum += w * value_noise(pos + float(k) * t, u_brush_size, 7919u);
    wsum += w;
  }
  imageStore(u_out, p, vec4(sum / wsum + 0.5 * lightness(c.rgb), 0.0, 0.0, 1.0));
}
#endif

#ifdef PASS_SHADE
#include "paint_relief.glsl"
uniform float u_relief;
const float GLOSS = 0.25;  // weight of the ridges' highlight

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (!covered(c)) {
    imageStore(u_out, p, c);
    return;
  }
  imageStore(u_out, p, vec4(lit_paint(c.rgb, relief_slope(p), u_relief, GLOSS), c.a));
}
#endif
