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
layout(std430, binding = 11) readonly buffer Opacity { float splat_opacity[]; };  // opacity_draws
#include "compact_records.glsl"

uniform int u_has_spacing;
uniform int u_has_curvature;
uniform int u_has_opacity;
uniform float u_color_median;  // the cloud's median colour luminance (0: the constant colour)
uniform sampler2D u_xtoon_image;

bool has_spacing() { return u_has_spacing != 0; }
float point_spacing(uint index) { return spacing[index]; }
bool has_curvature() { return u_has_curvature != 0; }
float point_curvature(uint index) { return curvature[index]; }
bool has_opacity() { return u_has_opacity != 0; }
float point_opacity(uint index) { return splat_opacity[index]; }
vec3 point_color(uint index) { return source_color(index).rgb; }
float point_color_median() { return u_color_median; }
vec4 xtoon_image(vec2 uv) { return texture(u_xtoon_image, uv); }
#include "hatching_kernels.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  Stroke s;
  bool alive = false;
  if (i < u_count) {
    uint index = u_first + (u_queue != 0 ? queue_order[u_first + i] : i);
    s = place_stroke(index, point_ids[index], u_view_from_chunk * vec4(point_position(index), 1.0), view_normal(index));
    alive = !(s.center_alpha.w <= 0.0);
  }
  uint slot = compact_record(alive, 12u);
  if (alive) {
    strokes[slot] = s;
    atomicAdd(kept, 1u);
    if (s.n_width.w < 0.0) atomicAdd(crossed, 1u);
  }
}
