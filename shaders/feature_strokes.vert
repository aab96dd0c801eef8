// Feature strokes, pass 2b: 6 vertices per record, a screen-aligned quad
// (seed 001 Fig. 5): r1 along the projected stroke direction (directional
// points) or the constant screen direction, r2 across it; texture
// coordinates (0,0) at -r1-r2 ... (1,1) at r1+r2, evaluated per fragment
// from its frame pixel (tiles: cpp/render/exact_raster.h).
#include "feature_strokes_common.glsl"
#include "exact_window.glsl"

uniform mat4 u_projection;
uniform ivec2 u_size;
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
uniform vec2 u_screen_dir;  // unit, pixels (x right, y up)

flat out vec4 v_color;
flat out float v_depth;
flat out uint v_primitive;
flat out uint v_id;
flat out float v_aspect;
flat out vec2 v_center;     // frame pixels
flat out vec2 v_r1;         // unit, along the stroke
flat out vec2 v_size;       // length, width (pixels)

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  uint r = uint(gl_VertexID) / 6u;
  vec2 corner = CORNERS[uint(gl_VertexID) % 6u];
  Record rec = records[r];
  vec3 c = rec.center_kind.xyz;
  float depth = -c.z;
  vec4 clip = u_projection * vec4(c, 1.0);
  precise vec2 center = (clip.xy / clip.w * 0.5 + 0.5) * vec2(u_size);
  vec2 r1 = u_screen_dir;
  if (rec.primitive == 1u) {
    r1 = vec2(1.0, 0.0);
  } else if (dot(rec.dir_length.xyz, rec.dir_length.xyz) > 0.5) {
    // The projected 3D direction, in pixels; along the view ray: the constant one.
    vec4 tip = u_projection * vec4(c + rec.dir_length.xyz * (u_ortho != 0 ? 1e-3 : 1e-3 * depth), 1.0);
    vec2 d = (tip.xy / tip.w - clip.xy / clip.w) * vec2(u_size);
    if (dot(d, d) > 1e-12) r1 = normalize(d);
  }
  vec2 r2 = vec2(-r1.y, r1.x);
  float len = rec.dir_length.w, width = rec.width;
  precise vec2 at = center + (2.0 * corner.x - 1.0) * 0.5 * len * r1 + (2.0 * corner.y - 1.0) * 0.5 * width * r2;
  // Reversed Z, as the visibility pass (whose discs lie behind the surface).
  float z = u_ortho != 0 ? 1.0 - (depth - u_near) / (u_far - u_near) : u_near / depth;
  gl_Position = exact_clip(exact_window(at), z);
  v_color = rec.color;
  v_depth = depth;
  v_primitive = rec.primitive;
  v_id = rec.point_id;
  v_aspect = len / max(width, 1e-3);
  v_center = center;
  v_r1 = r1;
  v_size = vec2(len, width);
}
