// Screen bounds of the pixels a segment covers, so that its filters run
// only there.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(r32f, binding = 0) uniform readonly image2D u_depth;
layout(std430, binding = 0) buffer Bounds { int bounds[4]; };

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  if (imageLoad(u_depth, p).r < INF) {
    atomicMin(bounds[0], p.x);
    atomicMin(bounds[1], p.y);
    atomicMax(bounds[2], p.x + 1);
    atomicMax(bounds[3], p.y + 1);
  }
}
