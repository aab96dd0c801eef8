// Posterize (cpp/filters/posterize.cpp), one pass.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform int u_levels;
uniform int u_space;  // 0 rgb, 1 Oklab lightness, 2 Oklab
uniform float u_smoothness;

// Quantizes x in [lo, hi] to u_levels values including both ends; a
// positive smoothness blends linearly near band borders.
float quantize(float x, float lo, float hi) {
  float steps = float(u_levels - 1);
  float t = clamp((x - lo) / (hi - lo), 0.0, 1.0) * steps;
  float q = floor(t + 0.5);
  if (u_smoothness > 0.0) {
    float f = t - q;  // [-0.5, 0.5]
    float w = 0.5 * u_smoothness;
    q += 0.5 * (smoothstep(0.5 - w, 0.5, f) - smoothstep(0.5 - w, 0.5, -f));
  }
  return lo + (hi - lo) * q / steps;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (covered(c)) {
    if (u_space == 0) {
      c.rgb = vec3(quantize(c.r, 0.0, 1.0), quantize(c.g, 0.0, 1.0), quantize(c.b, 0.0, 1.0));
    } else {
      vec3 lab = srgb_to_oklab(clamp(c.rgb, 0.0, 1.0));
      lab.x = quantize(lab.x, 0.0, 1.0);
      // Oklab a, b of sRGB colours lie within [-0.32, 0.32].
      if (u_space == 2) lab.yz = vec2(quantize(lab.y, -0.32, 0.32), quantize(lab.z, -0.32, 0.32));
      c.rgb = oklab_to_srgb(lab);
    }
  }
  imageStore(u_out, p, c);
}
