// brush_splats: the brush texture, a mixture of Gaussians (seed 004 eq. 1)
// on a 3 x 3 grid, evaluated per fragment (no texture images).
// PASS_DEPTH: the nearest brush surface (linear depth, GL depth written).
// PASS_BLEND: colour weighted by alpha (sum), transmittance (product),
// depth (min): order-independent.
// PASS_COUNT / PASS_STORE: the A-buffer (brush_abuffer.glsl): fragments
// counted per pixel, then stored in the pixel's list.
// variants: PASS_DEPTH | PASS_BLEND | PASS_COUNT | PASS_STORE | PASS_DEPTH TWO_LAYERS | PASS_BLEND TWO_LAYERS | PASS_COUNT TWO_LAYERS | PASS_STORE TWO_LAYERS
#if defined(PASS_BLEND) || defined(PASS_COUNT) || defined(PASS_STORE)
// Depth test first (no depth writes in these passes): only fragments near
// the surface are shaded and enter the blend or the lists.
layout(early_fragment_tests) in;
#endif
#if defined(PASS_COUNT) || defined(PASS_STORE)
#include "brush_abuffer.glsl"
#endif
in vec2 v_uv;
in float v_depth;
flat in vec4 v_color;
flat in vec3 v_cos;         // cos and sin of theta per column
flat in vec3 v_sin;
flat in uint v_id;
flat in int v_two_layers;  // the point's cluster asks for two layers
flat in float v_offset;    // the blend's offset (PASS_DEPTH: kept with the surface, for its rims)

#include "brush_texture.glsl"

#ifdef PASS_DEPTH
layout(location = 0) out vec4 o_depth;
layout(location = 1) out vec4 o_offset;
#elif defined(PASS_COUNT) || defined(PASS_STORE)
#else
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;
#endif

void main() {
  float a = brush_alpha(v_uv, v_cos, v_sin) * v_color.a;  // weighed by the splat's opacity
  vec3 rgb = v_color.rgb;
#ifdef TWO_LAYERS  // only where a style can ask for them: both sides of a branch cost
  if (u_layers > 1 || v_two_layers != 0) {
    // A second, smaller layer over the first, slightly altered colour.
    vec2 uv2 = (v_uv - 0.5) / u_layer_scale + 0.5;
    // Turned by the layer angle: cos(t + l), sin(t + l).
    float cl = cos(u_layer_angle), sl = sin(u_layer_angle);
    float a2 = brush_alpha(uv2, v_cos * cl - v_sin * sl, v_sin * cl + v_cos * sl) * v_color.a;
    vec3 rgb2 = u_layer_tint >= 0.0 ? mix(rgb, vec3(1.0), u_layer_tint) : rgb * (1.0 + u_layer_tint);
    float a_total = a2 + a * (1.0 - a2);
    rgb = a_total > 0.0 ? (rgb2 * a2 + rgb * a * (1.0 - a2)) / a_total : rgb;
    a = a_total;
  }
#endif
#ifdef PASS_DEPTH
  if (!(a >= u_surface_cut)) discard;  // the surface: brushes that cover half the pixel
#else
  if (!(a >= u_cut)) discard;
#endif
#ifdef PASS_DEPTH
  o_depth = vec4(v_depth);
  o_offset = vec4(v_offset);
#elif defined(PASS_COUNT)
  uint before = atomicAdd(counts[pixel_of(ivec2(gl_FragCoord.xy))], 1u);
  atomicMax(row_base[u_list_size.y + 1], before + 1u);  // the longest list
#elif defined(PASS_STORE)
  ivec2 q = ivec2(gl_FragCoord.xy);
  uint pixel = pixel_of(q);
  uint slot = atomicAdd(cursors[pixel], 1u);
  if (slot < counts[pixel]) {
    uint at = list_start(q) + slot;
    fragments[at] = Fragment(v_depth, v_id, packHalf2x16(rgb.rg), packHalf2x16(vec2(rgb.b, a)));
  }
#else
  o_accum = vec4(rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(v_depth);
#endif
}
