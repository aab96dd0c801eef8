// Feature strokes, pass 2a: what each of the chunk's first u_drawn queue
// points draws (seed 001 sections 5.2, 5.3, 6.2, 6.3).
#include "point_attributes.glsl"
#include "feature_strokes_common.glsl"

layout(local_size_x = 128) in;
layout(std430, binding = 3) readonly buffer Degree { float degree[]; };
layout(std430, binding = 4) readonly buffer Lines { uint lines[]; };      // snorm8 x3 direction, unorm8 error
layout(std430, binding = 5) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices in queue order
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 8) buffer Counters { uint counts[3]; };
layout(std430, binding = 9) readonly buffer Resolution { float resolution[]; };
#include "compact_records.glsl"

uniform uint u_drawn;          // queue points of this chunk to consider
uniform int u_queue;           // 1: read queue_order
uniform float u_near;
uniform float u_far;
uniform float u_threshold;
uniform float u_line_error;
uniform int u_use_lines;
uniform int u_has_lines;
uniform float u_dither;
uniform float u_dither_tone;
uniform float u_inv_median_r;
uniform int u_has_color;
uniform int u_prim_directional;
uniform int u_prim_other;
uniform int u_prim_dither;
uniform float u_directional_length;
uniform float u_other_length;
uniform float u_sprite_size;
uniform float u_stroke_width;
uniform float u_line_width;
uniform int u_point_coloring;
uniform float u_opacity;
uniform uint u_seed;

bool place(uint j, out Record rec) {
  rec.center_kind = vec4(0.0);
  rec.dir_length = vec4(0.0);
  rec.color = vec4(0.0);
  rec.point_id = 0u;
  rec.primitive = 0u;
  rec.width = 0.0;
  rec.pad = 0.0;
  uint local = u_queue != 0 ? queue_order[u_first + j] : j;
  uint index = u_first + local;
  uint id = point_ids[index];
  rec.point_id = id;
  vec4 v = u_view_from_chunk * vec4(point_position(index), 1.0);
  float depth = -v.z;
  if (!(depth >= u_near && depth <= u_far)) return false;

  float fd = degree[index];
  bool feature = fd == fd && fd > u_threshold;
  vec4 color = source_color(index);
  uint kind;
  vec3 dir = vec3(0.0);
  if (feature) {
    kind = 1u;
    if (u_use_lines != 0 && u_has_lines != 0) {
      uint line_bits = lines[index];
      float err = float(line_bits >> 24) / 255.0;
      vec3 d = unpackSnorm4x8(line_bits).xyz;
      if (dot(d, d) > 0.25 && err < u_line_error) {
        kind = 0u;
        dir = normalize(mat3(u_view_from_chunk) * d);
      }
    }
  } else {
    // Range-aware dithering for unorganised clouds: odds by the point's
    // share of surface (its spacing squared, relative to the cloud's median)
    // so the kept points are uniform in 3D, raised where the colour is dark.
    float r = resolution[index];
    float rel = r == r ? r * u_inv_median_r : 1.0;
    float lum = u_has_color != 0 ? dot(color.rgb, vec3(0.2126, 0.7152, 0.0722)) : 0.5;
    float odds = u_dither * rel * rel * mix(1.0, 2.0 * (1.0 - lum), u_dither_tone);
    if (id_rand(id, 1u, u_seed) >= odds) return false;
    kind = 2u;
  }
  int prim = kind == 0u ? u_prim_directional : kind == 1u ? u_prim_other : u_prim_dither;
  if (prim == 0 || u_opacity <= 0.0) return false;
  float len = kind == 0u ? u_directional_length : u_other_length;
  float width = prim == 3 ? u_stroke_width : u_line_width;
  if (prim == 1) { len = u_sprite_size; width = u_sprite_size; }
  rec.center_kind = vec4(v.xyz, float(kind));
  rec.dir_length = vec4(dir, len);
  rec.color = vec4(clamp(u_point_coloring != 0 ? color.rgb : u_constant_color.rgb, 0.0, 1.0), u_opacity);
  rec.primitive = uint(prim);
  rec.width = width;
  return true;
}

void main() {
  uint j = gl_GlobalInvocationID.x;
  Record rec;
  bool alive = j < u_drawn && place(j, rec);
  uint slot = compact_record(alive, 6u);
  if (alive) {
    records[slot] = rec;
    atomicAdd(counts[uint(rec.center_kind.w)], 1u);
  }
}
