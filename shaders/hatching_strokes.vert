// Hatching, pass 2: 12 vertices per point record, two quads (the second
// only for crossing strokes); records without a stroke make no triangle.
// Corners are drawn at their exact frame positions and the fragment shader
// finds each pixel's place on the stroke from its frame pixel (tiles:
// cpp/render/exact_raster.h).
#include "hatching_common.glsl"
#include "exact_window.glsl"

uniform mat4 u_projection;
uniform ivec2 u_size;          // the frame's (the projection maps to it)
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
uniform float u_px_per_unit;
uniform float u_offset_radii;  // move toward the camera by this many depth-disc radii
uniform int u_world_units;
uniform float u_disc_size;     // depth-disc diameter (px or scene units)

flat out vec4 v_color;         // display sRGB, alpha = opacity
flat out float v_aspect;       // length / width
flat out uint v_id;
flat out vec3 v_center;        // view space
flat out vec3 v_along;         // unit, the line
flat out vec3 v_across;        // unit, across it
flat out vec2 v_size;          // length, width (scene units)
flat out float v_offset;       // toward the camera (scene units)
flat out vec2 v_center_px;     // the centre's frame pixel

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

vec2 frame_pixel(vec3 p) {
  vec4 clip = u_projection * vec4(p, 1.0);
  precise vec2 px = (clip.xy / clip.w * 0.5 + 0.5) * vec2(u_size);
  return px;
}

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
  // A stroke reaching in front of the near plane would project through the
  // camera: not drawn (its point lies within half a stroke of the plane).
  float nearest = depth - 0.5 * len * abs(d.z) - 0.5 * width * abs(across.z);
  if (!(nearest >= u_near)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec3 p = center + d * (corner.x - 0.5) * len + across * (corner.y - 0.5) * width;
  // The paper's polygon offset, in scene units along the view ray (the
  // screen position is unchanged; the fragment shader applies it to depth):
  // disc radii at this depth.
  float disc_radius = 0.5 * (u_world_units != 0 ? u_disc_size : u_disc_size / px_per_unit);
  gl_Position = exact_clip(exact_window(frame_pixel(p)), 0.5);
  v_color = vec4(s.color, alpha);
  v_aspect = len / width;
  v_id = s.point_id * 2u + line;
  v_center = center;
  v_along = d;
  v_across = across;
  v_size = vec2(len, width);
  v_offset = u_offset_radii * disc_radius;
  v_center_px = frame_pixel(center);
}
