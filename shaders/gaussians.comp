// The gaussians mark's compositing on GL (cpp/marks/gaussians/gl.cpp): one
// 16 x 16 workgroup per screen tile, each pixel walking the tile's splats in
// their sorted order (view depth, point key) front to back, as the native
// path does (cpp/marks/gaussians/native.cpp); splat_alpha() is the shared
// kernel's (gaussians_kernels.glsl).
#include "shared_kernels.glsl"
#include "gaussians_settings.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

struct Record {
  vec4 center_depth_opacity;
  vec4 conic;
  vec4 color;
  ivec4 box;  // x0, y0, x1, y1 relative to the clip's corner
};
layout(std430, binding = 0) readonly buffer Records { Record records[]; };
layout(std430, binding = 1) readonly buffer Starts { uint starts[]; };
layout(std430, binding = 2) readonly buffer Lists { uint lists[]; };
layout(rgba32f, binding = 0) uniform writeonly image2D u_color;
layout(r32f, binding = 1) uniform writeonly image2D u_depth;
uniform ivec2 u_clip_min;
uniform ivec2 u_size;
uniform int u_tiles_x;
uniform float u_depth_alpha;
uniform float u_min_coverage;  // pixels less opaque than this are left empty

// The kernels' SH fetch (the colours were evaluated on the host).
vec3 sh_at(uint base, int k) { return vec3(0.0); }
#include "gaussians_kernels.glsl"

void main() {
  ivec2 local = ivec2(gl_GlobalInvocationID.xy);
  if (local.x >= u_size.x || local.y >= u_size.y) return;
  float none = uintBitsToFloat(0x7F800000u);
  uint t = gl_WorkGroupID.y * uint(u_tiles_x) + gl_WorkGroupID.x;
  float px = float(u_clip_min.x + local.x) + 0.5;
  float py = float(u_clip_min.y + local.y) + 0.5;
  float T = 1.0;
  vec3 C = vec3(0.0);
  float d = none;
  float best_weight = 0.0;
  float best_depth = none;
  for (uint i = starts[t]; i < starts[t + 1u]; ++i) {
    Record r = records[lists[i]];
    if (local.x < r.box.x || local.x > r.box.z || local.y < r.box.y || local.y > r.box.w) continue;
    float alpha = splat_alpha(r.conic.xyz, r.center_depth_opacity.w, r.center_depth_opacity.x - px,
                              r.center_depth_opacity.y - py);
    if (alpha == 0.0) continue;
    float test = T * (1.0 - alpha);
    if (test < 1e-4) break;
    float weight = alpha * T;
    C += r.color.rgb * weight;
    if (weight > best_weight) {
      best_weight = weight;
      best_depth = r.center_depth_opacity.z;
    }
    if (d == none && 1.0 - test >= u_depth_alpha) d = r.center_depth_opacity.z;
    T = test;
  }
  ivec2 p = u_clip_min + local;
  float a = 1.0 - T;
  if (!(a > 0.0) || a < u_min_coverage) {
    imageStore(u_color, p, vec4(0.0));
    imageStore(u_depth, p, vec4(none));
    return;
  }
  imageStore(u_color, p, vec4(clamp(C / a, 0.0, 1.0), a));
  imageStore(u_depth, p, vec4(d != none ? d : best_depth));
}
