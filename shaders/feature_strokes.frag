// Feature strokes, pass 2b: the primitive's alpha (Gaussian sprite, solid
// line, textured stroke: feature_strokes_sprite.glsl, shared with the native
// backend), blended order-independently: colour weighted by alpha (sum),
// transmittance (product), depth (min).
#include "feature_strokes_common.glsl"

uniform sampler2D u_texture_image;
vec4 stroke_image(vec2 uv) { return texture(u_texture_image, uv); }
#include "feature_strokes_sprite.glsl"

flat in StrokeSprite v_sprite;

uniform ivec2 u_origin;  // the images' frame pixel (0, 0)

layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;

void main() {
  float a = sprite_alpha(v_sprite, gl_FragCoord.xy + vec2(u_origin));
  if (!(a > 0.0)) discard;
  o_accum = vec4(v_sprite.color.rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(v_sprite.depth);
}
