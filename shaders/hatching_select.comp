// Hatching, pass 1: what each point draws (seed 002 sections 3.2-3.5; the
// kernels, shared with the native backend: hatching_kernels.glsl).
#include "point_attributes.glsl"
#include "hatching_common.glsl"
#include "shared_kernels.glsl"
#include "hatching_settings.glsl"

layout(local_size_x = 128) in;
layout(std430, binding = 3) readonly buffer Curvature { float curvature[]; };
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 8) buffer Counters { uint kept; uint crossed; };
layout(std430, binding = 5) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices (u_queue)
uniform int u_queue;  // 1: invocation i draws the chunk's i-th point of the resolution queue
layout(std430, binding = 9) readonly buffer Spacing { float spacing[]; };  // mean distance to 8 neighbours
struct DrawCommand { uint count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = 10) writeonly buffer Commands { DrawCommand commands[]; };

uniform uint u_out_base;      // first record slot of the chunk (a multiple of 128)
uniform uint u_command_base;  // first draw command of the chunk
uniform int u_has_spacing;
uniform int u_has_curvature;
uniform sampler2D u_xtoon_image;

bool has_spacing() { return u_has_spacing != 0; }
float point_spacing(uint index) { return spacing[index]; }
bool has_curvature() { return u_has_curvature != 0; }
float point_curvature(uint index) { return curvature[index]; }
vec3 point_color(uint index) { return source_color(index).rgb; }
vec4 xtoon_image(vec2 uv) { return texture(u_xtoon_image, uv); }
#include "hatching_kernels.glsl"

// Records are compacted per workgroup in point order (a prefix sum in
// shared memory), each workgroup issuing one indirect draw of its records:
// only surviving strokes reach the rasterizer, in an order that never
// depends on timing.
shared uint s_scan[128];

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint lid = gl_LocalInvocationID.x;
  Stroke s;
  bool alive = false;
  if (i < u_count) {
    uint index = u_first + (u_queue != 0 ? queue_order[u_first + i] : i);
    s = place_stroke(index, point_ids[index], u_view_from_chunk * vec4(point_position(index), 1.0), view_normal(index));
    alive = !(s.center_alpha.w <= 0.0);
  }
  s_scan[lid] = alive ? 1u : 0u;
  barrier();
  for (uint offset = 1u; offset < 128u; offset <<= 1u) {
    uint before = lid >= offset ? s_scan[lid - offset] : 0u;
    barrier();
    s_scan[lid] += before;
    barrier();
  }
  uint base = u_out_base + gl_WorkGroupID.x * 128u;
  if (alive) {
    strokes[base + s_scan[lid] - 1u] = s;
    atomicAdd(kept, 1u);
    if (s.n_width.w < 0.0) atomicAdd(crossed, 1u);
  }
  if (lid == 127u) commands[u_command_base + gl_WorkGroupID.x] = DrawCommand(12u * s_scan[127], 1u, 12u * base, 0u);
}
