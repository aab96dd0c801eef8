// brush_splats with tile_invariant: one instance per point, a triangle
// strip of four vertices, the splat of brush_splats.vert, textured by
// brush_splats_tiled.frag.
//
// Tiles (cpp/render/tiling.h): every value a fragment sees comes from its
// frame pixel and flat per-splat data, never from interpolated varyings
// (whose rounding follows where a tile's window starts). The corners are
// placed by their frame pixel on a 1/256 grid, less the tile's origin,
// through a power-of-two viewport whose transform is exact (multiples of
// 1/256 under 2^16; points.vert does the same): the rasterizer, in 1/256
// fixed point, covers the same pixels in every tile.
#include "brush_common.glsl"
#include "exact_window.glsl"

uniform float u_offset_radii;  // PASS_BLEND ...: tested this many radii toward the camera ...
uniform float u_noise_offset;  // ... or at least this far (scene units: brush_noise_offset)
uniform vec2 u_frame_size;     // the frame's (the projection maps to it)

flat out vec3 v_center;        // view space
flat out vec3 v_u_axis;        // t / (2 radius stretch): u = dot(p - center, this) + 0.5
flat out vec3 v_v_axis;        // b / (2 radius)
flat out vec3 v_normal;        // the splat's plane
flat out float v_offset;       // scene units toward the camera (u_offset_radii radii, at least u_noise_offset)
flat out vec2 v_depth_range;   // the splat's view depths: a fragment's is clamped into them
flat out vec4 v_color;         // display sRGB
flat out vec3 v_cos;           // cos and sin of theta per column
flat out vec3 v_sin;
flat out uint v_id;
flat out int v_two_layers;

const vec2 CORNERS[4] = vec2[](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(1, 1));

void main() {
  uint index = splat_point(uint(gl_InstanceID));
  vec2 corner = CORNERS[gl_VertexID];
  BrushSplat s = brush_splat(index);
  // The whole splat beyond the near plane (the same test at every corner):
  // positions on the grid need no clipping.
  float reach_z = (abs(s.t.z) * s.stretch + abs(s.b.z)) * s.radius;
  if (!s.visible || -s.center.z - reach_z < u_near) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: no triangle
    return;
  }
  vec3 p = s.center + (s.t * ((corner.x - 0.5) * s.stretch) + s.b * (corner.y - 0.5)) * (2.0 * s.radius);
  vec4 clip = u_projection * vec4(p, 1.0);
  precise vec2 win = (clip.xy / clip.w * 0.5 + 0.5) * u_frame_size;
  vec2 ndc = exact_clip(exact_window(win), 0.0).xy;
  // GL depth: one value per splat, so no interpolation rounds it; the
  // depth pass writes its own per pixel (gl_FragDepth), the later passes
  // cull with this bound of the splat's nearest point (moved toward the
  // camera), which is never behind the fragment's own test (the shader's,
  // exact): hidden splats are dropped before shading.
  float depth = -s.center.z;
  float blend_offset = max(u_offset_radii * s.radius, u_noise_offset);
#ifdef PASS_DEPTH
  float offset = 0.0;  // the surface itself
#else
  float offset = blend_offset;
#endif
  float nearest = depth - reach_z - offset;
  float z = u_ortho != 0 ? 1.0 - (nearest - u_near) / (u_far - u_near) : u_near / max(nearest, 1e-30);
  gl_Position = vec4(ndc, clamp(z * (1.0 + 1e-5) + 1e-6, 0.0, 1.0), 1.0);
  v_depth_range = vec2(depth - reach_z, depth + reach_z);
  v_center = s.center;
  v_u_axis = s.t / (2.0 * s.radius * s.stretch);
  v_v_axis = s.b / (2.0 * s.radius);
  v_normal = cross(s.t, s.b);
  v_offset = blend_offset;  // (PASS_DEPTH: kept with the surface, for its rims)
  v_color = brush_color(index, s);
  uint id = point_ids[index];
  vec3 angles = brush_column_angles(id);
  v_cos = cos(angles);
  v_sin = sin(angles);
  v_id = id;
  v_two_layers = s.two_layers ? 1 : 0;
}
