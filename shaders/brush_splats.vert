// brush_splats: one instance per point, a triangle strip of four vertices:
// a surface-aligned rectangle in the point's tangent frame (2 radius
// across, 2 radius x stretch along), textured by brush_splats.frag.
#include "brush_common.glsl"

uniform float u_offset_radii;  // PASS_BLEND: moved toward the camera by this many radii ...
uniform float u_noise_offset;  // ... or at least this far (scene units: brush_noise_offset)

out vec2 v_uv;                 // texture coordinates in [0, 1]
out float v_depth;             // linear view depth on the splat's plane
flat out vec4 v_color;         // display sRGB
flat out vec3 v_cos;           // cos and sin of theta per column
flat out vec3 v_sin;
flat out uint v_id;
flat out int v_two_layers;
flat out float v_offset;       // the blend's offset (scene units; PASS_DEPTH writes it with the surface)

const vec2 CORNERS[4] = vec2[](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(1, 1));

void main() {
  uint index = splat_point(uint(gl_InstanceID));
  vec2 corner = CORNERS[gl_VertexID];
  BrushSplat s = brush_splat(index);
  if (!s.visible) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: no triangle
    return;
  }
  vec3 p = s.center + (s.t * ((corner.x - 0.5) * s.stretch) + s.b * (corner.y - 0.5)) * (2.0 * s.radius);
  v_depth = -p.z;
  // Toward the camera along the view ray (the screen position is kept).
  v_offset = max(u_offset_radii * s.radius, u_noise_offset);
#ifdef PASS_DEPTH
  float offset = 0.0;  // the surface itself
#else
  float offset = v_offset;
#endif
  if (u_ortho != 0) p.z += offset;
  else p *= max(1.0 - offset / max(length(p), 1e-20), 0.0);
  float pd = -p.z;
  vec4 clip = u_projection * vec4(p, 1.0);
  // Reversed Z: near / d for perspective, 1 - (d - near) / (far - near) orthographic.
  if (u_ortho != 0) gl_Position = vec4(clip.xy / clip.w, 1.0 - (pd - u_near) / (u_far - u_near), 1.0);
  else gl_Position = vec4(clip.xy, u_near, clip.w);
  v_uv = corner;
  v_color = brush_color(index, s);
  uint id = point_ids[index];
  vec3 angles = brush_column_angles(id);
  v_cos = cos(angles);
  v_sin = sin(angles);
  v_id = id;
  v_two_layers = s.two_layers ? 1 : 0;
}
