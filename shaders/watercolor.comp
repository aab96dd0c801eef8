// Watercolor (cpp/filters/watercolor.cpp), three passes.
// PASS_ABSTRACT_X: bilateral sums along x: A = (rgb*c*w, c*w), B = (c at sigma_fill)
// PASS_ABSTRACT_Y: along y, then writes (abstracted rgb, covered fraction f).
// PASS_COMPOSE:    wobble, edge darkening, density variation, granulation.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform float u_sigma;
uniform float u_fill_sigma;
uniform int u_radius;
uniform float u_fill_norm;

#if defined(PASS_ABSTRACT_X) || defined(PASS_ABSTRACT_Y)
layout(rgba32f, binding = 2) uniform writeonly image2D u_out_a;
layout(rgba32f, binding = 3) uniform writeonly image2D u_out_b;
layout(rgba32f, binding = 4) uniform readonly image2D u_in_a;
layout(rgba32f, binding = 5) uniform readonly image2D u_in_b;
uniform float u_tolerance;  // range sigma of the bilateral weights (sRGB units)

// The colour a pass sees at q: the input (x), or the x pass's normalized sums (y).
vec4 source(ivec2 q) {
#ifdef PASS_ABSTRACT_X
  vec4 c = imageLoad(u_in, q);
  return covered(c) ? vec4(c.rgb, 1.0) : vec4(0.0);
#else
  vec4 a = imageLoad(u_in_a, q);
  return a.w > 0.0 ? vec4(a.rgb / a.w, a.w) : vec4(0.0);
#endif
}

// Separable bilateral filter over covered pixels (Pham and van Vliet 2005):
// abstraction that keeps colour edges; plus a plain Gaussian of coverage.
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 size = imageSize(u_in);
#ifdef PASS_ABSTRACT_X
  const ivec2 axis = ivec2(1, 0);
#else
  const ivec2 axis = ivec2(0, 1);
#endif
  vec3 centre = source(p).rgb;
  float inv_range = 1.0 / (2.0 * u_tolerance * u_tolerance);
  vec4 a = vec4(0.0);
  float b = 0.0;
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = p + k * axis;
    if (!in_image(q, size)) continue;
    vec4 s = source(q);
    vec3 d = s.rgb - centre;
    float w = gauss(float(k * k), u_sigma) * exp(-dot(d, d) * inv_range);
#ifdef PASS_ABSTRACT_X
    a += w * vec4(s.rgb * s.w, s.w);
    b += gauss(float(k * k), u_fill_sigma) * s.w;
#else
    a += w * imageLoad(u_in_a, q);
    b += gauss(float(k * k), u_fill_sigma) * imageLoad(u_in_b, q).x;
#endif
  }
#ifdef PASS_ABSTRACT_X
  imageStore(u_out_a, p, a);
  imageStore(u_out_b, p, vec4(b, 0.0, 0.0, 0.0));
#else
  imageStore(u_out, p, vec4(a.w > 0.0 ? a.rgb / a.w : vec3(0.0), b / u_fill_norm));
#endif
}
#endif

#ifdef PASS_COMPOSE
layout(rgba32f, binding = 4) uniform readonly image2D u_abstract;
uniform float u_wobble;
uniform float u_wobble_scale;
uniform float u_edge_darkening;
uniform float u_density;
uniform float u_density_scale;
uniform float u_granulation;
uniform float u_paper_scale;
uniform uint u_seed;
uniform sampler2D u_paper;   // height map, white = peaks (when u_paper_image)
uniform int u_paper_image;
uniform float u_dry_brush;
uniform vec4 u_paper_color;

// Paper height in [0,1] at pixel position x (1 = a peak of the grain).
float paper_height(vec2 x) {
  if (u_paper_image != 0) return textureLod(u_paper, x / (u_paper_scale * vec2(textureSize(u_paper, 0))), 0.0).r;
  // fbm clusters around 0.5; stretched to span [0,1] like a normalised image.
  return clamp(0.5 + 2.0 * (fbm(x, u_paper_scale, 2, u_seed + 53u) - 0.5), 0.0, 1.0);
}

// (rgb * f, f) of the abstracted image, bilinear at frame pixel position x.
vec4 sample_abstract(vec2 x) {
  vec2 s = x - 0.5;
  ivec2 base = ivec2(floor(s));
  vec2 t = s - vec2(base);
  ivec2 size = imageSize(u_abstract);
  vec4 acc = vec4(0.0);
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      ivec2 q = base + ivec2(i, j) - u_origin;  // the tile's pixel
      if (!in_image(q, size)) continue;
      vec4 v = imageLoad(u_abstract, q);
      float w = (i == 1 ? t.x : 1.0 - t.x) * (j == 1 ? t.y : 1.0 - t.y);
      acc += w * vec4(v.rgb * v.a, v.a);
    }
  return acc;
}

vec3 colour_at(vec2 x) {
  vec4 s = sample_abstract(x);
  return s.a > 0.0 ? s.rgb / s.a : vec3(0.0);
}

// Bousseau's pigment density model: d > 1 darkens, d < 1 lightens.
vec3 density(vec3 c, float d) { return clamp(c - (c - c * c) * (d - 1.0), 0.0, 1.0); }

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  vec4 c = imageLoad(u_in, p);
  // Paper: smooth displacement, low-frequency turbulence, fine grain.
  vec2 offset = u_wobble * vec2(2.0 * fbm(pos, u_wobble_scale * 0.25, 3, u_seed + 11u) - 1.0,
                                2.0 * fbm(pos, u_wobble_scale * 0.25, 3, u_seed + 23u) - 1.0);
  float turbulence = fbm(pos, u_density_scale * 0.125, 4, u_seed + 37u);
  float height = paper_height(pos);
  vec4 s = sample_abstract(pos + offset);
  float f = s.a;
  vec3 rgb;
  float edge = 0.0, f_wet = 1.0;
  if (f >= 0.5) {
    // A wet region: abstracted colour; pigment gathers at colour edges and
    // where the region's coverage falls off towards its border.
    rgb = s.rgb / f;
    vec2 x = pos + offset;
    vec3 gx = colour_at(x + vec2(1.0, 0.0)) - colour_at(x - vec2(1.0, 0.0));
    vec3 gy = colour_at(x + vec2(0.0, 1.0)) - colour_at(x - vec2(0.0, 1.0));
    float gradient = clamp(2.0 * sqrt(dot(gx, gx) + dot(gy, gy)), 0.0, 1.0);
    float rim = 1.0 - smoothstep(0.5, 0.9, f);
    f_wet = f;
    edge = max(gradient, rim);
  } else if (covered(c) && sample_abstract(pos).a < 0.5) {
    rgb = c.rgb;  // a lone point: no wobble, no rim
  } else {
    imageStore(u_out, p, c);
    return;
  }
  rgb = density(rgb, 1.0 + u_edge_darkening * edge);
  rgb = density(rgb, 1.0 + u_density * (2.0 * turbulence - 1.0));
  // Pigment settles in the valleys (low height): denser there.
  rgb = density(rgb, 1.0 + u_granulation * (1.0 - 2.0 * height));
  if (u_dry_brush > 0.0) {
    // Drier along borders and in patches; only peaks above the threshold
    // take pigment.
    float dry_rim = 1.0 - smoothstep(0.5, 0.99, f_wet);  // reaches ~2 edge widths in
    float dryness = u_dry_brush * clamp(0.35 + 0.65 * dry_rim + (turbulence - 0.5), 0.0, 1.0);
    float threshold = mix(-0.1, 0.8, dryness);
    float pigment = smoothstep(threshold - 0.06, threshold + 0.06, height);
    rgb = mix(u_paper_color.rgb, rgb, pigment);
  }
  imageStore(u_out, p, vec4(rgb, 1.0));
}
#endif
