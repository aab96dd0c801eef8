// Adds one segment to the frame: scene-linear premultiplied "over" when the
// segment is in front (by depth, or always when layering), "under" otherwise.
// Inpainted depth marks pixels the filters added (not covered by points) by
// a negative sign: they are in front of empty pixels and of other added
// ones by depth, and behind any segment's points.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_color;
layout(r32f, binding = 1) uniform readonly image2D u_depth;
layout(rgba32f, binding = 2) uniform image2D u_accum;
layout(r32f, binding = 3) uniform image2D u_accum_depth;
layout(r32i, binding = 4) uniform iimage2D u_accum_index;
layout(r32i, binding = 5) uniform iimage2D u_accum_added;  // 1 where the front pixel was added by filters
uniform int u_mode;  // 0 layering, 1 depth test, 2 inpainted depth test
uniform int u_segment;

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_color, p);
  if (c.a <= 0.0) return;
  float stored = imageLoad(u_depth, p).r;
  int added = u_mode == 2 && stored < 0.0 ? 1 : 0;
  float d = abs(stored);
  vec4 seg = vec4(srgb_to_linear(clamp(c.rgb, 0.0, 1.0)) * c.a, c.a);
  vec4 acc = imageLoad(u_accum, p);
  float acc_depth = imageLoad(u_accum_depth, p).r;
  int acc_index = imageLoad(u_accum_index, p).r;
  int acc_added = imageLoad(u_accum_added, p).r;
  bool front = u_mode == 0 || acc.a <= 0.0 || added < acc_added || (added == acc_added && d < acc_depth);
  if (front) {
    acc = seg + (1.0 - seg.a) * acc;
    acc_depth = u_mode == 0 || added < acc_added ? d : min(d, acc_depth);
    acc_index = u_segment;
    acc_added = added;
  } else {
    acc = acc + (1.0 - acc.a) * seg;
  }
  imageStore(u_accum, p, acc);
  imageStore(u_accum_depth, p, vec4(acc_depth));
  imageStore(u_accum_index, p, ivec4(acc_index));
  imageStore(u_accum_added, p, ivec4(acc_added));
}
