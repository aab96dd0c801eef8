// brush_splats: each point's splat as the caller sees it
// (render(..., capture_marks=True)): centre, tangent, normal, size, colour.
#include "brush_common.glsl"
layout(local_size_x = 128) in;
struct SplatRecord {
  vec4 center_size;  // view-space centre, length of the splat along its tangent (scene units; <= 0: not drawn)
  vec4 tangent;      // view space, unit: the brush's x axis; w: 1 where its cluster gives it two layers
  vec4 normal;       // view space, unit
  vec4 color;        // display sRGB
};
layout(std430, binding = 7) writeonly buffer Records { SplatRecord records[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  uint index = splat_point(i);
  BrushSplat s = brush_splat(index);
  records[i] = SplatRecord(vec4(s.center, s.visible ? 2.0 * s.radius * s.stretch : 0.0), vec4(s.t, s.two_layers ? 1.0 : 0.0),
                           vec4(s.n, uintBitsToFloat(point_ids[index])), brush_color(index, s));
}
