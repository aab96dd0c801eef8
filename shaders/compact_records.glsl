// Records of a select pass compacted per workgroup of 128 in invocation
// order (a prefix sum in shared memory), each workgroup issuing one
// indirect draw of its records: only kept records reach the rasterizer, in
// an order that never depends on timing (the hatching and feature strokes
// marks; their native backends keep the same order by concatenating work
// items in point order).
struct DrawCommand { uint count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = 10) writeonly buffer Commands { DrawCommand commands[]; };
uniform uint u_out_base;      // first record slot of the chunk (a multiple of 128)
uniform uint u_command_base;  // first draw command of the chunk

shared uint s_scan[128];

// The slot of this invocation's record (meaningful where kept); every
// invocation of the workgroup calls it (it holds barriers). Writes the
// workgroup's draw command: `vertices` per kept record.
uint compact_record(bool kept, uint vertices) {
  uint lid = gl_LocalInvocationID.x;
  s_scan[lid] = kept ? 1u : 0u;
  barrier();
  for (uint offset = 1u; offset < 128u; offset <<= 1u) {
    uint before = lid >= offset ? s_scan[lid - offset] : 0u;
    barrier();
    s_scan[lid] += before;
    barrier();
  }
  uint base = u_out_base + gl_WorkGroupID.x * 128u;
  if (lid == 127u) commands[u_command_base + gl_WorkGroupID.x] = DrawCommand(vertices * s_scan[127], 1u, vertices * base, 0u);
  return base + s_scan[lid] - 1u;
}
