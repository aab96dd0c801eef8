// Flow-based oil paint (cpp/filters/flow_oil.cpp). The flow field is the
// structure tensor's edge direction (filters::structure_tensor); then:
// PASS_LAB:    Oklab colour and coverage of covered pixels.
// PASS_ACROSS: bilateral filter along the gradient (across the flow),
//              sampled bilinearly.
// PASS_ALONG:  bilateral filter along the flow curve, then the lightness's
//              soft bands (the palette).
// PASS_NOISE:  paint noise at each pixel's surface point, fixed to the
//              surface; no weight where the pixel has no depth (a gap).
// PASS_HEIGHT: the noise's line integral along the flow curve (bristle
//              streaks), stopping at colour edges, plus paint thickness from
//              lightness.
// PASS_SHADE:  the paint lit through the height field (paint_relief.glsl).
// Images hold (value, coverage) as (xyz, w); only covered pixels are
// written, from covered pixels only, so the background never bleeds in.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;

#ifdef PASS_LAB
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  imageStore(u_out, p, covered(c) ? vec4(srgb_to_oklab(clamp(c.rgb, 0.0, 1.0)), 1.0) : vec4(0.0));
}
#endif

#if defined(PASS_ACROSS) || defined(PASS_ALONG) || defined(PASS_HEIGHT)
#include "flow_curve.glsl"
layout(rgba32f, binding = 4) uniform readonly image2D u_src;
uniform ivec2 u_valid_min;  // u_src is valid in [u_valid_min, u_valid_max)
uniform ivec2 u_valid_max;
uniform float u_sigma;      // spatial sigma (px)
uniform int u_radius;       // steps each way
uniform float u_tolerance;  // range sigma (Oklab distance)

// (value * coverage, coverage) of u_src, bilinear at offset o from the
// centre of pixel p.
vec4 sample_src(ivec2 p, vec2 o) {
  vec2 fo = floor(o);
  ivec2 base = p + ivec2(fo);
  vec2 t = o - fo;
  vec4 acc = vec4(0.0);
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      ivec2 q = base + ivec2(i, j);
      if (any(lessThan(q, u_valid_min)) || any(greaterThanEqual(q, u_valid_max))) continue;
      vec4 v = imageLoad(u_src, q);
      acc += (i == 1 ? t.x : 1.0 - t.x) * (j == 1 ? t.y : 1.0 - t.y) * vec4(v.xyz * v.w, v.w);
    }
  return acc;
}

float range_weight(vec3 a, vec3 b) {
  vec3 d = a - b;
  return exp(-dot(d, d) / (2.0 * u_tolerance * u_tolerance));
}
#endif

#if defined(PASS_ACROSS) || defined(PASS_ALONG)
// Sample s (sums of value * coverage, coverage) k px from the centre,
// weighted by distance and by its colour's difference from the centre's.
vec4 bilateral(vec3 centre, vec4 s, int k) {
  if (s.w <= 0.0) return vec4(0.0);
  return gauss(float(k * k), u_sigma) * range_weight(s.xyz / s.w, centre) * s;
}
#endif

#ifdef PASS_HEIGHT
layout(rgba32f, binding = 6) uniform readonly image2D u_paint;  // PASS_ALONG's (Oklab, coverage)
uniform float u_brush_size;  // px: the noise's correlation length
uniform float u_ridge;       // the streaks' height over their width

// The noise sample (n * w, 0, 0, w) at offset o, weighted along the curve
// and by whether the paint there is the centre's colour (streaks stop at
// colour edges, as a brush stroke does at the border of its colour).
vec4 streak_sample(vec3 centre, ivec2 p, vec2 o, int k) {
  vec4 paint = imageLoad(u_paint, clamp(p + ivec2(floor(o + 0.5)), u_valid_min, u_valid_max - 1));
  if (paint.w <= 0.0) return vec4(0.0);
  return gauss(float(k * k), u_sigma) * range_weight(paint.xyz, centre) * sample_src(p, o);
}
#endif

#ifdef PASS_ACROSS
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_src, p);
  if (c.w <= 0.0) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  vec2 t = flow_tangent(p, vec2(0.0));
  vec2 n = vec2(t.y, -t.x);  // the gradient direction
  vec4 acc = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) acc += bilateral(c.xyz, sample_src(p, float(k) * n), k);
  imageStore(u_out, p, vec4(acc.xyz / acc.w, 1.0));
}
#endif

#ifdef PASS_ALONG
uniform int u_levels;  // lightness bands, 0 = none
uniform float u_band_sharpness;

// Lightness L in u_levels bands of equal width, each soft_step-ed towards
// its middle: a palette of lightnesses the colours gather to.
float bands(float L) {
  if (u_levels <= 0) return L;
  float x = L * float(u_levels);
  float middle = floor(x) + 0.5;
  return (middle + soft_step(u_band_sharpness, x - middle)) / float(u_levels);
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_src, p);
  if (c.w <= 0.0) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  vec4 acc = bilateral(c.xyz, sample_src(p, vec2(0.0)), 0);
  for (int side = -1; side <= 1; side += 2) {
    vec2 o = vec2(0.0), dir = float(side) * flow_tangent(p, o);
    for (int k = 1; k <= u_radius; ++k) {
      flow_step(p, o, dir);
      acc += bilateral(c.xyz, sample_src(p, o), k);
    }
  }
  vec3 lab = acc.xyz / acc.w;
  imageStore(u_out, p, vec4(bands(lab.x), lab.yz, 1.0));
}
#endif

#ifdef PASS_NOISE
layout(r32f, binding = 2) uniform readonly image2D u_depth;  // linear view depth, +inf = empty
uniform float u_brush_size;
uniform uint u_seed;

// Gradient noise at the pixel's point in the segment's object space, its
// feature u_brush_size px on screen (surface_fbm: the pattern stays on the
// scan as the camera moves and keeps its size on screen).
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  float d = imageLoad(u_depth, p).r;
  if (!covered(imageLoad(u_in, p)) || isinf(d)) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  float n = surface_fbm(surface_point(pos, d), surface_pixel(d), u_brush_size, 1, u_seed);
  imageStore(u_out, p, vec4(n, 0.0, 0.0, 1.0));
}
#endif

#ifdef PASS_HEIGHT
// The streaks: the noise's weighted mean along the flow curve, scaled to
// unit variance (a mean of noise correlated over b px, with weights w, has
// the variance b sum(w^2) / sum(w)^2, at most 1), so their contrast does
// not depend on their length. Height in px: ridges u_ridge of the brush's
// width tall, plus as much paint again per unit of lightness.
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 paint = imageLoad(u_paint, p);
  if (paint.w <= 0.0) {
    imageStore(u_out, p, vec4(0.0));
    return;
  }
  vec4 acc = streak_sample(paint.xyz, p, vec2(0.0), 0);
  float w2 = acc.w * acc.w;
  for (int side = -1; side <= 1; side += 2) {
    vec2 o = vec2(0.0), dir = float(side) * flow_tangent(p, o);
    for (int k = 1; k <= u_radius; ++k) {
      flow_step(p, o, dir);
      vec4 s = streak_sample(paint.xyz, p, o, k);
      acc += s;
      w2 += s.w * s.w;
    }
  }
  float streak = 0.0;
  if (acc.w > 0.0) streak = acc.x / acc.w / sqrt(min(u_brush_size * w2 / (acc.w * acc.w), 1.0));
  imageStore(u_out, p, vec4(u_ridge * u_brush_size * (streak + paint.x), 0.0, 0.0, 1.0));
}
#endif

#ifdef PASS_SHADE
#include "paint_relief.glsl"
layout(rgba32f, binding = 6) uniform readonly image2D u_paint;
uniform int u_relief;  // 0: flat paint
uniform float u_gloss;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (!covered(c)) {
    imageStore(u_out, p, c);
    return;
  }
  vec3 rgb = oklab_to_srgb(imageLoad(u_paint, p).xyz);
  if (u_relief != 0) rgb = lit_paint(rgb, relief_slope(p), 1.0, u_gloss);
  imageStore(u_out, p, vec4(rgb, c.a));
}
#endif
