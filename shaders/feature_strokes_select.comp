// Feature strokes, pass 2a: what each of the chunk's first u_drawn queue
// points draws (seed 001 sections 5.2, 5.3, 6.2, 6.3), and past them, up to
// u_visited, the links of chains.
#include "point_attributes.glsl"
#include "feature_strokes_common.glsl"

layout(local_size_x = 128) in;
layout(std430, binding = 3) readonly buffer Degree { float degree[]; };
layout(std430, binding = 4) readonly buffer Lines { uint lines[]; };  // 3 a point: line, chain link, its length
layout(std430, binding = 5) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices in queue order
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 8) buffer Counters { uint counts[3]; };
layout(std430, binding = 9) readonly buffer Resolution { float resolution[]; };
layout(std430, binding = 11) readonly buffer Opacity { float splat_opacity[]; };  // opacity_draws
#include "compact_records.glsl"

uniform uint u_drawn;          // queue points of this chunk to consider
uniform uint u_visited;        // and past them, while chains draw, those that only draw a link
uniform int u_queue;           // 1: read queue_order
uniform int u_has_lines;
uniform float u_inv_median_r;
uniform float u_max_r;  // the chunk's largest local resolution (FeatureStrokeSettings::max_r)
uniform int u_has_color;
uniform int u_lit;             // shading applies to this chunk (normals bound)
uniform int u_has_opacity;     // opacity_draws: the splats' opacities bound

float point_degree(uint index) { return degree[index]; }
bool has_lines() { return u_has_lines != 0; }
uint point_line(uint index) { return lines[3u * index]; }
uint point_link(uint index) { return lines[3u * index + 1u]; }
float point_link_length(uint index) { return uintBitsToFloat(lines[3u * index + 2u]); }
float point_resolution(uint index) { return resolution[index]; }
float inv_median_r() { return u_inv_median_r; }
float max_r() { return u_max_r; }
bool has_color() { return u_has_color != 0; }
vec4 point_color(uint index) { return source_color(index); }
mat3 view_rotation() { return mat3(u_view_from_chunk); }
bool lit() { return u_lit != 0; }
vec3 point_normal(uint index) { return view_normal(index); }
bool has_opacity() { return u_has_opacity != 0; }
float point_opacity(uint index) { return splat_opacity[index]; }
#include "feature_strokes_kernels.glsl"

void main() {
  uint j = gl_GlobalInvocationID.x;
  Record rec;
  bool alive = false;
  if (j < u_visited) {
    uint index = u_first + (u_queue != 0 ? queue_order[u_first + j] : j);
    rec = place_record(index, point_ids[index], u_view_from_chunk * vec4(point_position(index), 1.0), j < u_drawn);
    alive = rec.primitive != 0u;
  }
  uint slot = compact_record(alive, 6u);
  if (alive) {
    records[slot] = rec;
    atomicAdd(counts[uint(rec.center_kind.w)], 1u);
  }
}
