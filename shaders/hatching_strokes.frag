// Hatching, pass 2: a stroke's texture, blended order-independently:
// colour weighted by alpha (sum), transmittance (product), depth (min).
// The pixel's place on the stroke comes from its frame pixel's view ray
// met with the stroke's plane (not interpolated varyings, whose rounding
// follows a tile's origin: cpp/render/exact_raster.h), and so does the
// depth the depth test sees.
#include "hatching_common.glsl"

flat in vec4 v_color;
flat in float v_aspect;
flat in uint v_id;
flat in vec3 v_center;
flat in vec3 v_along;
flat in vec3 v_across;
flat in vec2 v_size;
flat in float v_offset;
flat in vec2 v_center_px;

uniform ivec2 u_origin;             // the images' frame pixel (0, 0)
uniform ivec2 u_size;               // the frame's
uniform mat4 u_inv_projection;
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
uniform float u_max_reach;          // pixels from the centre a stroke may reach (its tiles' halo)
uniform int u_texture;              // pencil, crayon, ink, soft
uniform int u_clip_to_surface;
uniform sampler2D u_surface_depth;  // linear depth of the depth pass, +inf = none

layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;


float stroke_alpha(vec2 uv) {
  float across = abs(2.0 * uv.y - 1.0);
  float along = 2.0 * uv.x - 1.0;
  if (u_texture == 2) return 1.0;  // ink: solid
  if (u_texture == 3) {            // soft dot
    vec2 q = vec2(along * max(v_aspect, 1.0), 2.0 * uv.y - 1.0);
    return exp(-2.5 * dot(q, q) / max(v_aspect, 1.0));
  }
  // Tapered ends and pressure along the stroke.
  float taper = smoothstep(0.0, 0.18, uv.x) * smoothstep(1.0, 0.75, uv.x);
  vec2 q = vec2(uv.x * v_aspect * 1.5, uv.y * 2.0);
  if (u_texture == 1) {  // crayon: flat across, waxy gaps
    float g = id_value_noise(q * vec2(1.0, 1.5), v_id);
    return (1.0 - pow(across, 6.0)) * smoothstep(0.25, 0.6, g) * (0.6 + 0.4 * taper);
  }
  float g = id_value_noise(q, v_id);  // pencil: graphite profile with grain
  return (1.0 - across * across) * taper * (0.55 + 0.45 * g);
}

void main() {
  if (u_clip_to_surface != 0 && isinf(texelFetch(u_surface_depth, ivec2(gl_FragCoord.xy), 0).r)) discard;
  vec2 frame_px = gl_FragCoord.xy + vec2(u_origin);
  // Perspective close-ups: no stroke reaches farther than the halo allows.
  if (distance(frame_px, v_center_px) > u_max_reach) discard;
  // The pixel's view ray (from the near plane) met with the stroke's plane.
  vec4 near_point = u_inv_projection * vec4(frame_px / vec2(u_size) * 2.0 - 1.0, -1.0, 1.0);
  vec3 on_near = near_point.xyz / near_point.w;
  vec3 origin = u_ortho != 0 ? on_near : vec3(0.0);
  vec3 ray = u_ortho != 0 ? vec3(0.0, 0.0, -1.0) : on_near;
  vec3 normal = cross(v_along, v_across);
  vec3 q = origin + ray * (dot(v_center - origin, normal) / dot(ray, normal));
  vec3 rel = q - v_center;
  vec2 uv = vec2(dot(rel, v_along), dot(rel, v_across)) / v_size + 0.5;
  if (!(abs(uv.x) < 1e6 && abs(uv.y) < 1e6)) discard;  // the plane seen edge-on (or NaN)
  float a = clamp(v_color.a * stroke_alpha(uv), 0.0, 1.0);
  if (!(a > 0.0)) discard;
  // The depth test's depth: the stroke moved toward the camera by the offset.
  float pd = u_ortho != 0 ? -q.z - v_offset : -q.z * max(1.0 - v_offset / max(length(q), 1e-20), 0.0);
  float z = u_ortho != 0 ? 1.0 - (pd - u_near) / (u_far - u_near) : u_near / max(pd, 1e-30);
  gl_FragDepth = clamp(z, 0.0, 1.0);
  o_accum = vec4(v_color.rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(-(v_center + v_along * (uv.x - 0.5) * v_size.x).z);  // the surface's depth, not the offset one
}
