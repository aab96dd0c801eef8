// brush_splats A-buffer resolve: each pixel's list sorted completely by
// (depth, point id, colour) - an insertion sort in place, so the order the
// fragments arrived in never shows - then alpha-blended front to back into
// the segment's colour (straight alpha = coverage) and depth.
#include "common.glsl"
#include "brush_abuffer.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform writeonly image2D u_color;
layout(r32f, binding = 1) uniform image2D u_depth;  // in: the depth pass; out: the segment's depth

bool before(Fragment a, Fragment b) {
  if (a.depth != b.depth) return a.depth < b.depth;
  if (a.id != b.id) return a.id < b.id;
  if (a.rg != b.rg) return a.rg < b.rg;
  return a.ba < b.ba;
}

void main() {
  ivec2 q;
  if (!rect_pixel(q)) return;
  uint n = counts[pixel_of(q)];
  uint start = list_start(q);
  for (uint i = 1u; i < n; ++i) {
    Fragment f = fragments[start + i];
    uint j = i;
    while (j > 0u && before(f, fragments[start + j - 1u])) {
      fragments[start + j] = fragments[start + j - 1u];
      --j;
    }
    fragments[start + j] = f;
  }
  vec3 color = vec3(0.0);  // premultiplied
  float transmittance = 1.0;
  for (uint i = 0u; i < n; ++i) {
    Fragment f = fragments[start + i];
    vec2 rg = unpackHalf2x16(f.rg), ba = unpackHalf2x16(f.ba);
    color += transmittance * ba.y * vec3(rg, ba.x);
    transmittance *= 1.0 - ba.y;
  }
  float alpha = 1.0 - transmittance;
  if (n > 0u && alpha > 0.0) {
    float surface = imageLoad(u_depth, q).r;
    imageStore(u_color, q, vec4(clamp(color / alpha, 0.0, 1.0), alpha));
    imageStore(u_depth, q, vec4(isinf(surface) ? fragments[start].depth : surface));
  } else {
    imageStore(u_color, q, vec4(0.0));
    imageStore(u_depth, q, vec4(INF));
  }
}
