// Pencil hatching (cpp/filters/hatching.cpp), one pass.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform int u_layers;
uniform float u_angle;
uniform float u_spacing;
uniform float u_line_width;
uniform float u_stroke_length;
uniform float u_grain;
uniform float u_color_mix;
uniform int u_smooth;
uniform uint u_seed;
uniform vec4 u_pencil;
uniform vec4 u_paper;

// Ink of one layer of parallel strokes at angle `a`, full strength (0..1),
// with the stroke width scaled by `weight`.
float strokes(vec2 pos, float a, float weight, uint seed) {
  vec2 dir = vec2(cos(a), sin(a));
  vec2 nrm = vec2(-dir.y, dir.x);
  float along = dot(pos, dir);
  float across = dot(pos, nrm) / u_spacing;
  int line = int(floor(across));
  // Dashes: each line is cut into strokes of varying length and offset.
  float offset = hash01(ivec2(line, 0), seed) * u_stroke_length;
  float t = (along + offset) / u_stroke_length;
  int dash = int(floor(t));
  float f = fract(t);
  float keep = hash01(ivec2(line, dash), seed + 1u);
  if (keep < 0.12) return 0.0;  // a missing stroke now and then
  // Tapered ends, slight wobble and a per-stroke pressure.
  float taper = smoothstep(0.0, 0.08, f) * smoothstep(1.0, 0.85, f);
  float wobble = 0.15 * (value_noise(vec2(along, float(line) * 7.0), u_stroke_length * 0.5, seed + 2u) - 0.5);
  float centre = (fract(across) - 0.5 - wobble) * u_spacing;
  float width = u_line_width * weight * (0.7 + 0.3 * hash01(ivec2(dash, line), seed + 3u));
  float ink = clamp(0.5 * width + 0.5 - abs(centre), 0.0, 1.0);
  return ink * taper * (0.75 + 0.25 * keep);
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
  vec2 pos = vec2(p) + 0.5;
  const float offsets[4] = float[4](0.0, 1.5707963, 0.7853982, -0.7853982);
  float ink = 0.0;
  float band = 1.0 / float(u_layers);
  for (int i = 0; i < u_layers; ++i) {
    // Layer i fades in over tone [i band, (i+1) band] (first one from 0.05).
    float lo = float(i) * band + (i == 0 ? 0.05 : 0.0);
    float weight = clamp((tone - lo) / (float(i + 1) * band - lo), 0.0, 1.0);
    if (weight <= 0.0) continue;
    float s = strokes(pos, u_angle + offsets[i], 0.5 + 1.5 * weight, u_seed + uint(i) * 17u) * weight;
    ink = 1.0 - (1.0 - ink) * (1.0 - s);
  }
  float grain = fbm(pos, 1.5, 2, u_seed + 101u);
  ink *= (1.0 - 0.6 * u_grain * (1.0 - smoothstep(0.2, 0.8, grain))) * u_pencil.a;
  vec3 paper = mix(u_paper.rgb, c.rgb, u_color_mix);
  imageStore(u_out, p, vec4(mix(paper, u_pencil.rgb, ink), c.a));
}
