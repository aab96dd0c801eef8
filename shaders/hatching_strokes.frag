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
  vec4 hit = stroke_hit(v_quad, gl_FragCoord.xy + vec2(u_origin));
  float a = stroke_coverage(v_quad, hit);
  if (!(a > 0.0)) discard;
  gl_FragDepth = hit.z;
  o_accum = vec4(v_quad.color.rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(hit.w);
}
