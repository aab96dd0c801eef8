// Feature strokes, pass 1 (seed 001 section 6.1, visibility splatting):
// every point an opaque disc whose diameter is its local resolution
// projected (hole-free), in its tangent plane (feature_strokes_disc.glsl), pushed away along the view ray by u_offset local
// resolutions so strokes on the visible surface pass the depth test.
#include "point_attributes.glsl"
#include "exact_window.glsl"
#include "feature_strokes_disc.glsl"

layout(std430, binding = 9) readonly buffer Resolution { float resolution[]; };  // mean distance to 8 neighbours

uniform mat4 u_projection;
uniform ivec2 u_size;
uniform float u_near;
uniform float u_far;
uniform int u_ortho;
uniform float u_px_per_unit;
uniform float u_disc_scale;
uniform float u_offset;
uniform float u_max_size;
uniform float u_max_r;  // the chunk's largest local resolution (FeatureStrokeSettings::max_r)
uniform int u_disc_normals;  // 1: normals bound (binding 2): discs in the tangent plane

flat out float v_depth;
flat out float v_diameter;
flat out vec2 v_center;  // window position in the images (pixels)
flat out vec3 v_shape;   // feature_strokes_disc.glsl's disc_shape

void main() {
  uint index = uint(gl_VertexID);
  vec4 v = u_view_from_chunk * vec4(point_position(index), 1.0);
  float depth = -v.z;
  float r = resolution[index];
  if (!(r == r) || r < 0.0) r = 0.0;
  r = min(r, u_max_r);
  float w = u_ortho != 0 ? 1.0 : depth;
  float diameter = clamp(u_disc_scale * r * u_px_per_unit / max(w, 1e-30), 1.0, u_max_size);
  v_depth = depth;
  v_diameter = diameter;
  v_shape = disc_shape(u_disc_normals != 0 ? view_normal(index) : vec3(0.0), v.xyz, u_ortho != 0);
  gl_PointSize = diameter;
  if (!(depth >= u_near && depth <= u_far)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume
    return;
  }
  vec4 clip = u_projection * v;
  // The frame pixel, drawn at the same subpixel place in every tile.
  precise vec2 frame_px = (clip.xy / clip.w * 0.5 + 0.5) * vec2(u_size);
  vec2 win = exact_window(frame_px);
  v_center = win;
  float pushed = depth + u_offset * r;
  float z = u_ortho != 0 ? 1.0 - (pushed - u_near) / (u_far - u_near) : u_near / pushed;
  gl_Position = exact_clip(win, max(z, 0.0));
}
