// Shared helpers. Images are straight-alpha, display sRGB in [0,1] until
// the compositor converts them to scene-linear premultiplied.
// Not a const: uintBitsToFloat is no constant expression in strict GLSL 4.50.
#define INF uintBitsToFloat(0x7F800000u)

uniform ivec2 u_rect_min;  // pixels processed: [u_rect_min, u_rect_max)
uniform ivec2 u_rect_max;
// The frame pixel of the images' (0, 0) (a tile's origin; cpp/render/
// tiling.h): whatever depends on the pixel's place in the frame (noise,
// patterns, surface points) uses p + u_origin, so tiles match the frame.
uniform ivec2 u_origin;

// The pixel of this invocation, or false when outside the rect.
bool rect_pixel(out ivec2 p) {
  p = u_rect_min + ivec2(gl_GlobalInvocationID.xy);
  return all(lessThan(p, u_rect_max));
}

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

vec3 srgb_to_linear(vec3 c) {
  return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

// Integer hash (lowbias32, id_hash.glsl): noise seeded by indices, never by time or address.
#include "id_hash.glsl"
uint hash_u32(uint x) { return id_hash(x); }
