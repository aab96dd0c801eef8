// out(p) = in(p - d(p)), d transverse to the travel direction. Bilinear
// sampling on premultiplied colour so background does not bleed in.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
uniform float u_amplitude;
uniform float u_wavelength;
uniform vec2 u_direction;
uniform float u_phase;

vec4 fetch_premultiplied(ivec2 frame_q) {
  ivec2 q = frame_q - u_origin;  // the tile's pixel
  ivec2 size = imageSize(u_in);
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) return vec4(0.0);
  vec4 c = imageLoad(u_in, q);
  return vec4(c.rgb * c.a, c.a);
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  float along = dot(pos, u_direction);
  vec2 across = vec2(-u_direction.y, u_direction.x);
  vec2 src = pos - across * u_amplitude * sin(6.28318530718 * along / u_wavelength - u_phase) - 0.5;
  ivec2 base = ivec2(floor(src));
  vec2 f = src - vec2(base);
  vec4 c = mix(mix(fetch_premultiplied(base), fetch_premultiplied(base + ivec2(1, 0)), f.x),
               mix(fetch_premultiplied(base + ivec2(0, 1)), fetch_premultiplied(base + ivec2(1, 1)), f.x), f.y);
  // Keep edges crisp: coverage below half a pixel is background.
  vec4 outc = c.a > 0.5 ? vec4(c.rgb / c.a, 1.0) : vec4(0.0);
  imageStore(u_out, p, outc);
}
