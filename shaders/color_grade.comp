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
  }
  imageStore(u_out, p, c);
}
