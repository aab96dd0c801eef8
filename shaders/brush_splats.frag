// brush_splats: the brush texture, a mixture of Gaussians (seed 004 eq. 1)
// on a 3 x 3 grid, evaluated per fragment (no texture images).
// Every fragment finds its point on the splat from its frame pixel: the
// pixel's view ray met with the splat's plane (flat per-splat data only,
// so a tile computes the frame's bits; brush_splats.vert).
// PASS_DEPTH: the nearest brush surface: an atomic minimum of the linear
// depth's bits in the segment's depth image (order-independent).
// PASS_BLEND: the splats near that surface (within v_offset toward the
// camera): colour weighted by alpha (sum), transmittance (product), depth
// (min): order-independent.
// PASS_COUNT / PASS_STORE: the A-buffer (brush_abuffer.glsl): fragments
// counted per pixel, then stored in the pixel's list.
// variants: PASS_DEPTH | PASS_BLEND | PASS_COUNT | PASS_STORE, TWO_LAYERS
#if defined(PASS_COUNT) || defined(PASS_STORE)
#include "brush_abuffer.glsl"
#endif
flat in vec3 v_center;
flat in vec3 v_u_axis;
flat in vec3 v_v_axis;
flat in vec3 v_normal;
flat in float v_offset;
flat in vec4 v_color;
flat in vec3 v_cos;         // cos and sin of theta per column
flat in vec3 v_sin;
flat in uint v_id;
flat in int v_two_layers;  // the point's cluster asks for two layers

uniform ivec2 u_origin;        // the tile's, in frame pixels
uniform mat4 u_view_from_pixel;// frame pixel (x, y, 0, 1) -> its ray's point on the near plane (homogeneous)
uniform int u_ortho;
#ifdef PASS_DEPTH
layout(r32ui, binding = 0) uniform coherent uimage2D u_nearest;  // the segment's depth (R32F) as bits
#else
layout(r32f, binding = 0) uniform readonly image2D u_surface;    // the depth pass's nearest depth
#endif
uniform int u_gaussians;     // 1..9
uniform float u_amplitude;   // A
uniform float u_dev;         // spacing of the centres
uniform float u_lambda;      // shape exponent
uniform float u_sigma_x;
uniform float u_sigma_y;
uniform int u_layers;        // 1 or 2
uniform float u_layer_scale; // second layer: the grid shrunk about the centre
uniform float u_layer_angle; // ... and turned (radians)
uniform float u_layer_tint;  // ... and its colour toward white (> 0) or black (< 0)
uniform float u_cut;         // alpha below this is no coverage
uniform float u_reach;       // |q| beyond which a Gaussian adds less than u_cut / (A N) (skipped)

#if defined(PASS_BLEND)
layout(location = 0) out vec4 o_accum;
layout(location = 1) out vec4 o_reveal;
layout(location = 2) out vec4 o_depth;
#endif

// |(x_theta - x0) / sx|, |(y_theta - y0) / sy| of eq. 1: uv relative to
// the centre c, turned by theta (cos cs, sin sn).
vec2 brush_q(vec2 uv, vec2 c, float cs, float sn) {
  vec2 d = uv - c;
  vec2 r = vec2(cs * d.x - sn * d.y, sn * d.x + cs * d.y);
  return abs(r) / vec2(u_sigma_x, u_sigma_y);
}

// The mixture of eq. 1: rows = ceil(N / 3) rows of up to three columns,
// dev apart, centred on the texture; column c turned by angles[c].
// Gaussians beyond u_reach add less than the cut allows to matter: they
// count as 0. Clamped to 1.
// The loops have constant bounds so that they unroll and each column's
// angle is read at a constant index: a software rasterizer runs fragments
// in lock-step lanes, and an index that varies per lane goes through
// memory (and a branch costs both of its sides anyway).
float brush_alpha(vec2 uv, vec3 cs, vec3 sn) {
  int rows = (u_gaussians + 2) / 3;
  float sum = 0.0;
  for (int row = 0; row < 3; ++row) {
    int cols = clamp(u_gaussians - row * 3, 0, 3);
    for (int col = 0; col < 3; ++col) {
      vec2 c = vec2(0.5 + (float(col) - 0.5 * float(cols - 1)) * u_dev, 0.5 + (float(row) - 0.5 * float(rows - 1)) * u_dev);
      vec2 q = brush_q(uv, c, cs[col], sn[col]);
      float g = exp(-0.5 * (pow(q.x, u_lambda) + pow(q.y, u_lambda)));
      if (col < cols && q.x <= u_reach && q.y <= u_reach) sum += g;
    }
  }
  return clamp(u_amplitude * sum, 0.0, 1.0);
}

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
  float depth = -p.z;
  if (!(depth > 0.0 && depth < 3.0e38)) discard;  // the plane seen edge on
#ifdef PASS_DEPTH
  // Nearer than what the pixel holds so far (a bound only: the minimum is atomic).
  uint bits = floatBitsToUint(depth);
  if (bits >= imageLoad(u_nearest, q).r) discard;
#else
  // Near the surface: the point moved toward the camera along its ray by
  // v_offset is not behind the nearest brush.
  float moved = u_ortho != 0 ? depth - v_offset : depth * max(1.0 - v_offset / max(length(p), 1e-20), 0.0);
  if (!(moved <= imageLoad(u_surface, q).r)) discard;
#endif
  vec3 rel = p - v_center;
  vec2 uv = vec2(dot(rel, v_u_axis), dot(rel, v_v_axis)) + 0.5;
  float a = brush_alpha(uv, v_cos, v_sin);
  vec3 rgb = v_color.rgb;
#ifdef TWO_LAYERS  // only where a style can ask for them: both sides of a branch cost
  if (u_layers > 1 || v_two_layers != 0) {
    // A second, smaller layer over the first, slightly altered colour.
    vec2 uv2 = (uv - 0.5) / u_layer_scale + 0.5;
    // Turned by the layer angle: cos(t + l), sin(t + l).
    float cl = cos(u_layer_angle), sl = sin(u_layer_angle);
    float a2 = brush_alpha(uv2, v_cos * cl - v_sin * sl, v_sin * cl + v_cos * sl);
    vec3 rgb2 = u_layer_tint >= 0.0 ? mix(rgb, vec3(1.0), u_layer_tint) : rgb * (1.0 + u_layer_tint);
    float a_total = a2 + a * (1.0 - a2);
    rgb = a_total > 0.0 ? (rgb2 * a2 + rgb * a * (1.0 - a2)) / a_total : rgb;
    a = a_total;
  }
#endif
  if (!(a >= u_cut)) discard;
#ifdef PASS_DEPTH
  imageAtomicMin(u_nearest, q, bits);
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
