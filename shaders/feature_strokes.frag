// Feature strokes, pass 2b: the primitive's alpha (Gaussian sprite, solid
// line, textured stroke), blended order-independently: colour weighted by
// alpha (sum), transmittance (product), depth (min).
#include "feature_strokes_common.glsl"

flat in vec4 v_color;
flat in float v_depth;
flat in uint v_primitive;
flat in uint v_id;
flat in float v_aspect;
flat in vec2 v_center;
flat in vec2 v_r1;
flat in vec2 v_size;

uniform ivec2 u_origin;  // the images' frame pixel (0, 0)

uniform int u_texture;  // taper, brush, dry, image
uniform sampler2D u_texture_image;

layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;


float stroke_alpha(vec2 uv) {
  float across = abs(2.0 * uv.y - 1.0);
  if (u_texture == 3) {
    vec4 t = texture(u_texture_image, uv);
    return t.a * (1.0 - dot(t.rgb, vec3(0.2126, 0.7152, 0.0722)));
  }
  if (u_texture == 1) {  // bristle brush: streaks across, each fading out at its own length
    float bristle = floor(uv.y * 7.0);
    uint h = id_hash(v_id * 7u + uint(bristle));
    float reach = 0.65 + 0.35 * float(h >> 8) / 16777216.0;
    float ink = 0.55 + 0.45 * float(id_hash(h) >> 8) / 16777216.0;
    return ink * smoothstep(0.0, 0.08, uv.x) * (1.0 - smoothstep(reach - 0.15, reach, uv.x)) *
           (1.0 - pow(across, 8.0));
  }
  float taper = smoothstep(0.0, 0.2, uv.x) * (1.0 - smoothstep(0.7, 1.0, uv.x));
  if (u_texture == 2) {  // dry brush: broken by grain along the stroke
    float g = id_value_noise(vec2(uv.x * v_aspect * 2.0, uv.y * 5.0), v_id);
    return taper * smoothstep(0.3, 0.55, g) * (1.0 - pow(across, 4.0));
  }
  return taper * (1.0 - across * across);  // taper: pointed ends, round profile
}

void main() {
  // Texture coordinates of the frame pixel (not interpolated varyings, whose
  // rounding follows a tile's origin).
  vec2 rel = gl_FragCoord.xy + vec2(u_origin) - v_center;
  vec2 r2 = vec2(-v_r1.y, v_r1.x);
  vec2 v_uv = vec2(dot(rel, v_r1), dot(rel, r2)) / max(v_size, vec2(1e-6)) + 0.5;
  float k;
  if (v_primitive == 1u) {  // Gaussian splatting kernel (Fig. 4a)
    vec2 q = 2.0 * v_uv - 1.0;
    float d2 = dot(q, q);
    if (d2 > 1.0) discard;
    k = exp(-d2 / (2.0 * 0.4 * 0.4));
  } else if (v_primitive == 2u) {
    k = 1.0;
  } else {
    k = stroke_alpha(v_uv);
  }
  float a = clamp(v_color.a * k, 0.0, 1.0);
  if (!(a > 0.0)) discard;
  o_accum = vec4(v_color.rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(v_depth);
}
