// Colour grading (cpp/filters/color_grade.cpp), one pass.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform float u_gain;
uniform float u_contrast;
uniform float u_saturation;
uniform vec2 u_hue;  // cos, sin of the rotation
uniform float u_gamma;
uniform vec4 u_tint;  // display sRGB
uniform sampler2D u_lut;     // strip layout: x = red + N blue, y = green
uniform float u_lut_size;    // N; 0 = no look-up table
uniform float u_lut_strength;

// Trilinear lookup: bilinear within the two nearest blue slices, then a mix.
vec3 look_up(vec3 c) {
  float n = u_lut_size;
  vec3 f = clamp(c, 0.0, 1.0) * (n - 1.0);
  float b0 = floor(f.b);
  float b1 = min(b0 + 1.0, n - 1.0);
  vec2 uv0 = vec2((b0 * n + f.r + 0.5) / (n * n), (f.g + 0.5) / n);
  vec2 uv1 = vec2((b1 * n + f.r + 0.5) / (n * n), (f.g + 0.5) / n);
  return mix(textureLod(u_lut, uv0, 0.0).rgb, textureLod(u_lut, uv1, 0.0).rgb, f.b - b0);
}

const float MID_GREY_L = 0.5646;  // Oklab lightness of 18 % grey

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (covered(c)) {
    vec3 lin = srgb_to_linear(clamp(c.rgb, 0.0, 1.0)) * u_gain * srgb_to_linear(u_tint.rgb);
    lin = pow(max(lin, vec3(0.0)), vec3(u_gamma));
    vec3 lab = linear_to_oklab(lin);
    lab.x = MID_GREY_L + (lab.x - MID_GREY_L) * u_contrast;
    vec2 ab = lab.yz * u_saturation;
    lab.yz = vec2(u_hue.x * ab.x - u_hue.y * ab.y, u_hue.y * ab.x + u_hue.x * ab.y);
    c.rgb = clamp(linear_to_srgb(oklab_to_linear(lab)), 0.0, 1.0);
    if (u_lut_size >= 2.0) c.rgb = mix(c.rgb, clamp(look_up(c.rgb), 0.0, 1.0), u_lut_strength);
  }
  imageStore(u_out, p, c);
}
