// brush_splats with tile_invariant (brush_splats_tiled.vert): the passes of
// brush_splats.frag, but every fragment finds its point on the splat from
// its frame pixel: the pixel's view ray met with the splat's plane (flat
// per-splat data only, so a tile computes the frame's bits).
// PASS_DEPTH: the nearest brush surface (GL depth from the fragment's own
// depth, and its linear depth).
// PASS_BLEND: the splats near that surface (within v_offset toward the
// camera; culled by the GL depth test first, decided by the shader's own):
// colour weighted by alpha (sum), transmittance (product), depth (min).
// PASS_COUNT / PASS_STORE: the A-buffer (brush_abuffer.glsl): fragments
// counted per pixel, then stored in the pixel's list.
// variants: PASS_DEPTH | PASS_BLEND | PASS_COUNT | PASS_STORE | PASS_DEPTH TWO_LAYERS | PASS_BLEND TWO_LAYERS | PASS_COUNT TWO_LAYERS | PASS_STORE TWO_LAYERS
#ifndef PASS_DEPTH
// The GL depth test culls with a bound (brush_splats_tiled.vert): before shading.
layout(early_fragment_tests) in;
#endif
#if defined(PASS_COUNT) || defined(PASS_STORE)
#include "brush_abuffer.glsl"
#endif
flat in vec3 v_center;
flat in vec3 v_u_axis;
flat in vec3 v_v_axis;
flat in vec3 v_normal;
flat in float v_offset;
flat in vec2 v_depth_range;
flat in vec4 v_color;
flat in vec3 v_cos;         // cos and sin of theta per column
flat in vec3 v_sin;
flat in uint v_id;
flat in int v_two_layers;  // the point's cluster asks for two layers

uniform ivec2 u_origin;        // the tile's, in frame pixels
uniform mat4 u_view_from_pixel;// frame pixel (x, y, 0, 1) -> its ray's point on the near plane (homogeneous)
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
#ifndef PASS_DEPTH
layout(r32f, binding = 0) uniform readonly image2D u_surface;    // the depth pass's nearest depth
#endif
#include "brush_texture.glsl"

#ifdef PASS_DEPTH
layout(location = 0) out vec4 o_depth;
layout(location = 1) out vec4 o_offset;
#elif defined(PASS_BLEND)
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;
#endif

// The frame pixel's point on the splat's plane (view space): the ray from
// the camera (perspective) or along -z (orthographic) through the pixel.
vec3 plane_point(vec2 frame_pixel) {
  vec4 h = u_view_from_pixel * vec4(frame_pixel, 0.0, 1.0);
  vec3 on_ray = h.xyz / h.w;
  if (u_ortho != 0) return vec3(on_ray.xy, on_ray.z + dot(v_center - on_ray, v_normal) / v_normal.z);
  return on_ray * (dot(v_center, v_normal) / dot(on_ray, v_normal));
}

void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  vec3 p = plane_point(gl_FragCoord.xy + vec2(u_origin));
  if (!(abs(p.z) < 3.0e38)) discard;  // the plane seen edge on
  // Within the splat's depths (a pixel the grid's rounding let in beside a
  // sliver would extrapolate): the GL depth's bounds hold.
  float depth = clamp(-p.z, v_depth_range.x, v_depth_range.y);
#ifndef PASS_DEPTH
  // Near the surface: the point moved toward the camera along its ray by
  // v_offset is not behind the nearest brush.
  float moved = u_ortho != 0 ? depth - v_offset : depth * max(1.0 - v_offset / max(length(p), depth), 0.0);
  if (!(moved <= imageLoad(u_surface, q).r)) discard;
#endif
  vec3 rel = p - v_center;
  vec2 uv = vec2(dot(rel, v_u_axis), dot(rel, v_v_axis)) + 0.5;
  float a = brush_alpha(uv, v_cos, v_sin) * v_color.a;  // weighed by the splat's opacity
  vec3 rgb = v_color.rgb;
#ifdef TWO_LAYERS  // only where a style can ask for them: both sides of a branch cost
  if (u_layers > 1 || v_two_layers != 0) {
    // A second, smaller layer over the first, slightly altered colour.
    vec2 uv2 = (uv - 0.5) / u_layer_scale + 0.5;
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
  gl_FragDepth = clamp(u_ortho != 0 ? 1.0 - (depth - u_near) / (u_far - u_near) : u_near / depth, 0.0, 1.0);
  o_depth = vec4(depth);
  o_offset = vec4(v_offset);
#elif defined(PASS_COUNT)
  uint before = atomicAdd(counts[pixel_of(q)], 1u);
  atomicMax(row_base[u_list_size.y + 1], before + 1u);  // the longest list
#elif defined(PASS_STORE)
  uint pixel = pixel_of(q);
  uint slot = atomicAdd(cursors[pixel], 1u);
  if (slot < counts[pixel]) {
    uint at = list_start(q) + slot;
    fragments[at] = Fragment(depth, v_id, packHalf2x16(rgb.rg), packHalf2x16(vec2(rgb.b, a)));
  }
#else
  o_accum = vec4(rgb * a, a);
  o_reveal = vec4(a);
  o_depth = vec4(depth);
#endif
}
