// Hatching, pass 2: a stroke's texture, blended order-independently:
// colour weighted by alpha (sum), transmittance (product), depth (min).
#include "hatching_common.glsl"

in vec2 v_uv;
in float v_depth;
flat in vec4 v_color;
flat in float v_aspect;
flat in uint v_id;

uniform int u_texture;         // pencil, crayon, ink, soft
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
  float a = clamp(v_color.a * stroke_alpha(v_uv), 0.0, 1.0);
  if (a <= 0.0) discard;
  o_accum = vec4(v_color.rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(v_depth);
}
