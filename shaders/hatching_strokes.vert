// Hatching, pass 2: 12 vertices per point record, two quads (the second
// only for crossing strokes); records without a stroke make no triangle.
#include "hatching_common.glsl"

uniform mat4 u_projection;
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
uniform float u_px_per_unit;
uniform float u_offset_radii;  // move toward the camera by this many depth-disc radii
uniform int u_world_units;
uniform float u_disc_size;     // depth-disc diameter (px or scene units)

out vec2 v_uv;                 // x along the stroke, y across, in [0, 1]
out float v_depth;             // linear view depth
flat out vec4 v_color;         // display sRGB, alpha = opacity
flat out float v_aspect;       // length / width
flat out uint v_id;

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  uint record = uint(gl_VertexID) / 12u;
  uint line = (uint(gl_VertexID) % 12u) / 6u;
  vec2 corner = CORNERS[uint(gl_VertexID) % 6u];
  Stroke s = strokes[record];
  bool crossing = s.n_width.w < 0.0;
  if (!(s.center_alpha.w > 0.0) || (line == 1u && !crossing)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: no triangle
    return;
  }
  vec3 center = s.center_alpha.xyz;
  vec3 n = s.n_width.xyz;
  vec3 d = line == 0u ? s.d1_length.xyz : cross(n, s.d1_length.xyz);
  float len = s.d1_length.w, width = abs(s.n_width.w);
  float depth = -center.z;
  float px_per_unit = u_px_per_unit / (u_ortho != 0 ? 1.0 : depth);
  // Thin strokes are drawn 1.5 px wide with proportionally less opacity:
  // sub-pixel quads would drop pixels and shimmer as the camera moves.
  float width_px = width * px_per_unit;
  float alpha = s.center_alpha.w;
  if (width_px < 1.5) {
    alpha *= width_px / 1.5;
    width = 1.5 / px_per_unit;
  }
  // Across the stroke: perpendicular to the line and to the view ray.
  vec3 view_dir = u_ortho != 0 ? vec3(0.0, 0.0, -1.0) : normalize(center);
  vec3 across = cross(d, view_dir);
  if (dot(across, across) < 1e-8) across = cross(d, n);
  across = normalize(across);
  vec3 p = center + d * (corner.x - 0.5) * len + across * (corner.y - 0.5) * width;
  // The paper's polygon offset, in scene units along the view ray (so the
  // screen position is unchanged): disc radii at this depth.
  float disc_radius = 0.5 * (u_world_units != 0 ? u_disc_size : u_disc_size / px_per_unit);
  float offset = u_offset_radii * disc_radius;
  if (u_ortho != 0) p.z += offset;
  else p *= max(1.0 - offset / max(length(p), 1e-20), 0.0);
  float pd = -p.z;
  vec4 clip = u_projection * vec4(p, 1.0);
  // Reversed Z (as the depth pass): near / d for perspective, 1 - (d - near) / (far - near) orthographic.
  if (u_ortho != 0) gl_Position = vec4(clip.xy / clip.w, 1.0 - (pd - u_near) / (u_far - u_near), 1.0);
  else gl_Position = vec4(clip.xy, u_near, clip.w);
  v_uv = corner;
  v_depth = -(center + d * (corner.x - 0.5) * len).z;  // the surface's depth, not the offset one
  v_color = vec4(s.color, alpha);
  v_aspect = len / width;
  v_id = s.point_id * 2u + line;
}
