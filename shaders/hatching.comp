// Pencil hatching (cpp/filters/hatching.cpp), one pass.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(r32f, binding = 2) uniform readonly image2D u_depth;
uniform int u_layers;
uniform float u_angle;
uniform float u_spacing;
uniform float u_line_width;
uniform float u_stroke_length;
uniform float u_grain;
uniform float u_color_mix;
uniform int u_smooth;
uniform int u_fit_radius;
uniform int u_surface;  // 1: strokes anchored to the surface, 0: to the screen
uniform uint u_seed;
uniform vec4 u_pencil;
uniform vec4 u_paper;
#include "surface_fit.glsl"

const float LAYER_OFFSETS[4] = float[4](0.0, 1.5707963, 0.7853982, -0.7853982);

float stroke_ink(float distance_px, float width) { return clamp(0.5 * width + 0.5 - abs(distance_px), 0.0, 1.0); }

// Screen space: one layer of parallel strokes at angle `a`, broken into
// dashes of random length and offset, with a slight wobble.
float screen_strokes(vec2 pos, float a, float weight, uint seed) {
  vec2 dir = vec2(cos(a), sin(a));
  vec2 nrm = vec2(-dir.y, dir.x);
  float along = dot(pos, dir);
  float across = dot(pos, nrm) / u_spacing;
  int line = int(floor(across));
  float offset = hash01(ivec2(line, 0), seed) * u_stroke_length;
  float t = (along + offset) / u_stroke_length;
  int dash = int(floor(t));
  float f = fract(t);
  float keep = hash01(ivec2(line, dash), seed + 1u);
  if (keep < 0.12) return 0.0;  // a missing stroke now and then
  float taper = smoothstep(0.0, 0.08, f) * smoothstep(1.0, 0.85, f);
  float wobble = 0.15 * (value_noise(vec2(along, float(line) * 7.0), u_stroke_length * 0.5, seed + 2u) - 0.5);
  float centre = (fract(across) - 0.5 - wobble) * u_spacing;
  float width = u_line_width * weight * (0.7 + 0.3 * hash01(ivec2(dash, line), seed + 3u));
  return stroke_ink(centre, width) * taper * (0.75 + 0.25 * keep);
}

// Smooth [0,1] noise along a stroke, at a cell of `cell` world units, keyed
// by the stroke's own position `key` (so every stroke has its own pattern).
float along_noise(float along, float cell, float key, uint seed) {
  uint k = hash_u32(floatBitsToUint(key) ^ seed);
  return value_noise(vec2(along / cell, float(k & 1023u)), 1.0, seed + 5u);
}

// Surface space: the strokes of one layer are where the surface cuts a
// family of parallel planes of the segment's object space (normal `n`),
// so they stay on the surface as the camera moves. Plane spacing follows
// the view in powers of two (Benard et al.'s dynamic solid textures): at
// spacing 2^k every plane is drawn, the odd ones fade out as the ideal
// spacing grows to 2^(k+1), where only the even ones, the planes of the
// next level, remain; nothing jumps. `grad` is the gradient of dot(P, n)
// in world units per pixel.
float surface_strokes(vec3 P, vec3 n, vec3 along_dir, vec2 grad, float weight, uint seed) {
  float g = length(grad);
  if (!(g > 1e-12)) return 0.0;  // the surface lies in a plane of the family
  float level = log2(u_spacing * g);
  float k = floor(level), t = level - k;
  float S = exp2(k);
  float phase = dot(P, n) / S;
  float m = floor(phase + 0.5);
  float distance_px = (phase - m) * S / g;
  bool odd = mod(m, 2.0) != 0.0;
  float presence = odd ? 1.0 - t : 1.0;
  float key = m * S;  // the plane's own coordinate: the same at both levels
  float width = u_line_width * weight * (0.7 + 0.3 * hash01(ivec2(int(hash_u32(floatBitsToUint(key)) & 0xffffu), 0), seed + 3u));
  // Gaps between strokes: noise along the stroke at two scales around
  // `stroke_length` pixels, blended like the planes.
  float along = dot(P, along_dir);
  float dash_level = log2(u_stroke_length * g);
  float dk = floor(dash_level), dt = dash_level - dk;
  float gap = mix(along_noise(along, exp2(dk), key, seed), along_noise(along, exp2(dk + 1.0), key, seed + 7u), dt);
  float keep = smoothstep(0.18, 0.32, gap);
  return stroke_ink(distance_px, width) * presence * keep;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (!covered(c)) {
    imageStore(u_out, p, c);
    return;
  }
  // Tone over covered pixels in a small box.
  ivec2 size = imageSize(u_in);
  vec3 sum = vec3(0.0);
  float n = 0.0;
  for (int dy = -u_smooth; dy <= u_smooth; ++dy)
    for (int dx = -u_smooth; dx <= u_smooth; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (!in_image(q, size)) continue;
      vec4 s = imageLoad(u_in, q);
      if (covered(s)) sum += s.rgb, n += 1.0;
    }
  float tone = clamp(1.0 - lightness(sum / n), 0.0, 1.0);
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  SurfacePatch surface = u_surface != 0 ? fit_surface(p, u_fit_radius) : SurfacePatch(false, vec3(0.0), vec3(0.0), vec3(0.0));
  bool has_depth = surface.valid;
  vec3 P = surface.P, Px = surface.dPdx, Py = surface.dPdy;

  float ink = 0.0;
  float band = 1.0 / float(u_layers);
  for (int i = 0; i < u_layers; ++i) {
    // Layer i fades in over tone [i band, (i+1) band] (first one from 0.05).
    float lo = float(i) * band + (i == 0 ? 0.05 : 0.0);
    float weight = clamp((tone - lo) / (float(i + 1) * band - lo), 0.0, 1.0);
    if (weight <= 0.0) continue;
    float a = u_angle + LAYER_OFFSETS[i];
    uint seed = u_seed + uint(i) * 17u;
    float s;
    if (has_depth) {
      // Planes whose normal is tilted out of the object's xy plane cut
      // ground, roofs and walls alike; the strokes on a surface facing the
      // camera run along `a`.
      vec3 nrm = normalize(vec3(-sin(a), cos(a), 0.6));
      vec3 along_dir = vec3(cos(a), sin(a), 0.0);
      s = surface_strokes(P, nrm, along_dir, vec2(dot(Px, nrm), dot(Py, nrm)), 0.5 + 1.5 * weight, seed);
    } else {
      s = screen_strokes(pos, a, 0.5 + 1.5 * weight, seed);
    }
    ink = 1.0 - (1.0 - ink) * (1.0 - s * weight);
  }
  float grain = fbm(pos, 1.5, 2, u_seed + 101u);
  ink *= (1.0 - 0.6 * u_grain * (1.0 - smoothstep(0.2, 0.8, grain))) * u_pencil.a;
  vec3 paper = mix(u_paper.rgb, c.rgb, u_color_mix);
  imageStore(u_out, p, vec4(mix(paper, u_pencil.rgb, ink), c.a));
}
