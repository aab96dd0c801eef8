// Cartoon filter, two passes (see cpp/filters/cartoon.cpp).
// PASS_SMOOTH: per pixel, Gaussian means over covered neighbours only:
//   smooth = (mean colour, fraction of the fill_gaps disk that is covered)
//   edges  = (luminance at sigma_e, at 1.6 sigma_e, any covered weight, 0)
// PASS_COMPOSE: quantize, darken DoG edges, draw outlines outside.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
#ifdef PASS_SMOOTH
layout(rgba32f, binding = 2) uniform writeonly image2D u_smooth;
layout(rgba32f, binding = 3) uniform writeonly image2D u_edges;
uniform float u_sigma;
uniform int u_radius;
uniform int u_fill_gaps;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
  float se = u_sigma, sr = 1.6 * u_sigma;
  float we = 0.0, wr = 0.0, le = 0.0, lr = 0.0;
  vec3 rgb = vec3(0.0);
  float disk = 0.0, disk_covered = 0.0;
  int g2 = u_fill_gaps * u_fill_gaps;
  for (int dy = -u_radius; dy <= u_radius; ++dy) {
    for (int dx = -u_radius; dx <= u_radius; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      bool inside = all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size));
      vec4 c = inside ? imageLoad(u_in, q) : vec4(0.0);
      float d2 = float(dx * dx + dy * dy);
      if (dx * dx + dy * dy <= g2) {
        disk += 1.0;
        disk_covered += c.a > 0.0 ? 1.0 : 0.0;
      }
      if (c.a <= 0.0) continue;
      float L = luminance(c.rgb);
      float ke = exp(-d2 / (2.0 * se * se));
      float kr = exp(-d2 / (2.0 * sr * sr));
      we += ke; le += ke * L; rgb += ke * c.rgb;
      wr += kr; lr += kr * L;
    }
  }
  float coverage = disk > 0.0 ? disk_covered / disk : 0.0;
  imageStore(u_smooth, p, vec4(we > 0.0 ? rgb / we : vec3(0.0), coverage));
  imageStore(u_edges, p, vec4(we > 0.0 ? le / we : 0.0, wr > 0.0 ? lr / wr : 0.0, we > 0.0 ? 1.0 : 0.0, 0.0));
}
#endif

#ifdef PASS_COMPOSE
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(rgba32f, binding = 2) uniform readonly image2D u_smooth;
layout(rgba32f, binding = 3) uniform readonly image2D u_edges;
uniform int u_levels;
uniform float u_sharpness;
uniform float u_edge_sensitivity;
uniform float u_edge_strength;
uniform int u_outline_width;
uniform int u_fill_gaps;
uniform vec4 u_edge_color;

// Dense enough to cast an outline: at least half of the fill disk covered.
bool solid(ivec2 q) {
  ivec2 size = imageSize(u_in);
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) return false;
  return u_fill_gaps > 0 ? imageLoad(u_smooth, q).a >= 0.5 : imageLoad(u_in, q).a > 0.0;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  vec4 s = imageLoad(u_smooth, p);
  // A hole counts as surface when a third of its fill disk is covered, a
  // looser test than solid(), so interior holes are filled, not outlined.
  bool filled = c.a <= 0.0 && u_fill_gaps > 0 && s.a >= 0.3;
  if (c.a > 0.0 || filled) {
    vec3 base = c.a > 0.0 ? c.rgb : s.rgb;
    float L = luminance(base);
    float step_size = 1.0 / float(u_levels - 1);
    float q = floor(L / step_size + 0.5) * step_size;
    float Lq = q + 0.5 * step_size * tanh(u_sharpness * (L - q) / step_size);
    vec3 rgb = clamp(base * (Lq / max(L, 1e-4)), 0.0, 1.0);
    if (L < 1e-4) rgb = vec3(Lq);
    vec4 e = imageLoad(u_edges, p);
    float D = e.x - 0.98 * e.y;
    float E = D > 0.0 ? 1.0 : 1.0 + tanh(u_edge_sensitivity * D);
    rgb = mix(rgb, u_edge_color.rgb, (1.0 - E) * u_edge_strength);
    imageStore(u_out, p, vec4(rgb, 1.0));
    return;
  }
  // Outside the surface: outline if a solid pixel is within outline_width.
  int w = u_outline_width;
  for (int dy = -w; dy <= w; ++dy)
    for (int dx = -w; dx <= w; ++dx)
      if (dx * dx + dy * dy <= w * w && solid(p + ivec2(dx, dy))) {
        imageStore(u_out, p, u_edge_color);
        return;
      }
  imageStore(u_out, p, vec4(0.0));
}
#endif
