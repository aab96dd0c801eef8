// Hatching, pass 2: a stroke's texture, blended order-independently:
// colour weighted by alpha (sum), transmittance (product), depth (min).
// What a pixel gets: hatching_quad.glsl, shared with the native backend.
#include "hatching_common.glsl"
#include "shared_kernels.glsl"
#include "hatching_quad.glsl"

flat in StrokeQuad v_quad;

uniform ivec2 u_origin;             // the images' frame pixel (0, 0)
uniform sampler2D u_surface_depth;  // linear depth of the depth pass, +inf = none

layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;

void main() {
  if (raster.clip_to_surface != 0 && isinf(texelFetch(u_surface_depth, ivec2(gl_FragCoord.xy), 0).r)) discard;
  vec3 f = stroke_fragment(v_quad, gl_FragCoord.xy + vec2(u_origin));
  if (!(f.x > 0.0)) discard;
  gl_FragDepth = f.y;
  o_accum = vec4(v_quad.color.rgb * f.x, f.x);
  o_reveal = vec4(f.x);
  o_depth = vec4(f.z);
}
