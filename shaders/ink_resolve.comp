// Ink over paper (cpp/render/ink_layer.cpp) into the segment's colour
// (straight alpha) and depth: the depth pass's surface where there is one,
// else the ink's (strokes may reach past the silhouette); +inf where
// nothing is.
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform writeonly image2D u_color;
layout(r32f, binding = 1) uniform image2D u_depth;   // in: the depth pass; out: the segment's depth
layout(rgba32f, binding = 2) uniform readonly image2D u_accum;
layout(r32f, binding = 3) uniform readonly image2D u_reveal;
layout(r32f, binding = 4) uniform readonly image2D u_stroke_depth;
uniform ivec2 u_rect_min;
uniform ivec2 u_rect_max;
uniform vec4 u_paper;   // display sRGB, alpha = opacity over the surface
uniform int u_surface;  // 1: the depth image holds the depth pass

void main() {
  ivec2 q = ivec2(gl_GlobalInvocationID.xy) + u_rect_min;
  if (any(greaterThanEqual(q, u_rect_max))) return;
  float surface = u_surface != 0 ? imageLoad(u_depth, q).r : uintBitsToFloat(0x7f800000u);
  bool on_surface = !isinf(surface);
  float ink = 1.0 - clamp(imageLoad(u_reveal, q).r, 0.0, 1.0);
  vec4 acc = imageLoad(u_accum, q);
  vec3 ink_rgb = acc.a > 0.0 ? acc.rgb / acc.a : vec3(0.0);
  float paper = on_surface ? u_paper.a : 0.0;
  float alpha = ink + paper * (1.0 - ink);
  vec3 premultiplied = ink_rgb * ink + u_paper.rgb * paper * (1.0 - ink);
  if (alpha > 0.0) {
    imageStore(u_color, q, vec4(clamp(premultiplied / alpha, 0.0, 1.0), alpha));
    imageStore(u_depth, q, vec4(on_surface ? surface : imageLoad(u_stroke_depth, q).r));
  } else {
    imageStore(u_color, q, vec4(0.0));
    imageStore(u_depth, q, vec4(uintBitsToFloat(0x7f800000u)));
  }
}
