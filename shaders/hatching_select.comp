// Hatching, pass 1: what each point draws (seed 002 sections 3.2-3.5).
#include "point_attributes.glsl"
#include "hatching_common.glsl"

layout(local_size_x = 128) in;
layout(std430, binding = 3) readonly buffer Curvature { float curvature[]; };
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 8) buffer Counters { uint kept; uint crossed; };
layout(std430, binding = 5) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices (u_queue)
uniform int u_queue;  // 1: invocation i draws the chunk's i-th point of the resolution queue
layout(std430, binding = 9) readonly buffer Spacing { float spacing[]; };  // mean distance to 8 neighbours
struct DrawCommand { uint count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = 10) writeonly buffer Commands { DrawCommand commands[]; };

uniform uint u_out_base;      // first record slot of the chunk (a multiple of 128)
uniform uint u_command_base;  // first draw command of the chunk
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
uniform float u_depth_min;
uniform float u_depth_max;
uniform float u_px_per_unit;
uniform vec3 u_light_dir;   // towards the light, view space
uniform vec3 u_direction;   // line direction u, view space
uniform float u_ambient;
uniform float u_specular;
uniform int u_two_sided;
uniform float u_shininess;
uniform int u_xtoon;        // pencil, wax_crayon, two_colored, chalk, ink, image
uniform sampler2D u_xtoon_image;
uniform float u_density;
uniform float u_cross;
uniform float u_coverage;      // 0: off
uniform int u_has_spacing;
uniform int u_world_units;
uniform float u_length;
uniform float u_width;
uniform float u_length_jitter;
uniform float u_curvature_length;
uniform int u_has_curvature;
uniform float u_position_jitter;
uniform float u_angle_jitter;  // radians
uniform int u_coloring;        // constant, xtoon, point
uniform float u_point_blend;
uniform float u_hue_shift;     // turns
uniform int u_pencil_count;
uniform vec3 u_pencils[64];    // sorted by hue
uniform float u_pencil_hues[64];
uniform float u_opacity;
uniform float u_alpha_modification;
uniform float u_alpha_jitter;
uniform uint u_seed;

// The procedural X-Toon textures: x = brightness, y = depth (0 near). As
// the paper's (its Fig. 2) they leave depth unused, so which points draw
// never changes as the camera moves; an image texture may use it.
vec4 xtoon(vec2 uv) {
  float b = uv.x;
  if (u_xtoon == 0)  // pencil: graphite, strokes fade with the light
    return vec4(vec3(0.16, 0.16, 0.19), 1.0 - smoothstep(0.1, 0.95, b));
  if (u_xtoon == 1) {  // wax crayon: three bands of tone, warm colours
    float a = b < 0.35 ? 1.0 : b < 0.7 ? 0.6 : 0.22;
    return vec4(mix(vec3(0.45, 0.12, 0.10), vec3(0.98, 0.62, 0.18), b), a);
  }
  if (u_xtoon == 2)  // two-coloured: cool shadows to warm light
    return vec4(mix(vec3(0.12, 0.22, 0.62), vec3(0.96, 0.62, 0.22), smoothstep(0.0, 1.0, b)), 1.0 - 0.75 * b);
  if (u_xtoon == 3)  // chalk: light strokes where lit, for dark paper
    return vec4(vec3(0.95, 0.95, 0.9), smoothstep(0.15, 0.9, b));
  if (u_xtoon == 4)  // ink: dark strokes in the shade only
    return vec4(vec3(0.04, 0.04, 0.08), 1.0 - smoothstep(0.42, 0.5, b));
  return texture(u_xtoon_image, uv);
}

vec3 rgb_to_hsv(vec3 c) {
  float mx = max(c.r, max(c.g, c.b)), mn = min(c.r, min(c.g, c.b)), d = mx - mn;
  float h = 0.0;
  if (d > 0.0) {
    if (mx == c.r) h = mod((c.g - c.b) / d, 6.0);
    else if (mx == c.g) h = (c.b - c.r) / d + 2.0;
    else h = (c.r - c.g) / d + 4.0;
  }
  return vec3(h / 6.0, mx > 0.0 ? d / mx : 0.0, mx);
}
vec3 hsv_to_rgb(vec3 c) {
  vec3 k = clamp(abs(mod(c.x * 6.0 + vec3(0.0, 4.0, 2.0), 6.0) - 3.0) - 1.0, 0.0, 1.0);
  return c.z * mix(vec3(1.0), k, c.y);
}

// Section 3.3: the two pencils whose hues enclose the colour's, one chosen
// with probability by closeness, then mixed with black and white so value
// and saturation match.
vec3 quantize(vec3 c, uint id) {
  vec3 hsv = rgb_to_hsv(c);
  int n = u_pencil_count;
  int hi = 0;
  while (hi < n && u_pencil_hues[hi] <= hsv.x) ++hi;
  int i1 = (hi + n - 1) % n, i2 = hi % n;
  float h1 = u_pencil_hues[i1], h2 = u_pencil_hues[i2];
  float span = fract(h2 - h1 + 1.0), into = fract(hsv.x - h1 + 1.0);
  float a = span > 0.0 ? clamp(1.0 - into / span, 0.0, 1.0) : 1.0;  // weight of pencil 1
  vec3 pencil = id_rand(id, 5u, u_seed) < a ? u_pencils[i1] : u_pencils[i2];
  vec3 p = rgb_to_hsv(pencil);
  float chroma = p.y * p.z;
  float kc = chroma > 1e-4 ? clamp(hsv.y * hsv.z / chroma, 0.0, 1.0) : 0.0;
  float kw = clamp(hsv.z - kc * p.z, 0.0, 1.0 - kc);
  return kc * pencil + vec3(kw);
}

// The strokes of the chunk's point i, or false where it draws none.
bool place_stroke(uint i, out Stroke s) {
  uint index = u_first + (u_queue != 0 ? queue_order[u_first + i] : i);
  s.center_alpha = vec4(0.0);
  s.d1_length = vec4(0.0);
  s.n_width = vec4(0.0);
  s.color = vec3(0.0);
  uint id = point_ids[index];
  s.point_id = id;
  vec4 v = u_view_from_chunk * vec4(point_position(index), 1.0);
  float depth = -v.z;
  if (!(depth >= u_near && depth <= u_far)) {
    return false;
  }
  vec3 to_eye = u_ortho != 0 ? vec3(0.0, 0.0, 1.0) : normalize(-v.xyz);
  vec3 n = view_normal(index);
  if (n == vec3(0.0)) n = to_eye;  // no usable normal: a view-facing stroke
  // Two-sided: turned toward the camera (for clouds whose normals are not
  // consistently oriented; changes at silhouettes as the camera moves).
  else if (u_two_sided != 0 && dot(n, to_eye) < 0.0) n = -n;

  // X-Toon coordinates: brightness (diffuse + ambient + Phong) and depth.
  float diffuse = max(dot(n, u_light_dir), 0.0);
  float spec = u_specular > 0.0 ? u_specular * pow(max(dot(reflect(-u_light_dir, n), to_eye), 0.0), u_shininess) : 0.0;
  float brightness = clamp(u_ambient + (1.0 - u_ambient) * diffuse + spec, 0.0, 1.0);
  float depth01 = clamp((depth - u_depth_min) / max(u_depth_max - u_depth_min, 1e-6), 0.0, 1.0);
  vec4 tone = xtoon(vec2(brightness, depth01));
  float alpha_tex = clamp(tone.a, 0.0, 1.0);

  // Length and width in scene units (before the per-stroke variations).
  float scale = u_world_units != 0 ? 1.0 : (u_ortho != 0 ? 1.0 : depth) / u_px_per_unit;
  float base_len = u_length * scale;
  float width = u_width * scale;

  // Lighting by omission and cross vs parallel, by probabilistic
  // interpolation; the coverage limit scales the odds by the point's share
  // of the surface over a stroke's area (as many strokes per area however
  // dense or irregular the scan).
  float keep = alpha_tex * u_density;
  if (u_coverage > 0.0 && u_has_spacing != 0) {
    float r = spacing[index];
    float area = 0.88 * r * r;
    keep *= min(1.0, u_coverage * area / max(base_len * width * (1.0 + alpha_tex * u_cross), 1e-30));
  }
  if (id_rand(id, 0u, u_seed) >= keep) {
    return false;
  }
  bool crossing = id_rand(id, 1u, u_seed) < alpha_tex * u_cross;

  // d1 = u - (u.n) n; where u is (nearly) the normal, the axis least aligned with it.
  vec3 d1 = u_direction - dot(u_direction, n) * n;
  if (dot(d1, d1) < 1e-6) {
    vec3 a = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    d1 = a - dot(a, n) * n;
  }
  d1 = normalize(d1);
  if (u_angle_jitter > 0.0) {
    float t = u_angle_jitter * (2.0 * id_rand(id, 2u, u_seed) - 1.0);
    d1 = normalize(cos(t) * d1 + sin(t) * cross(n, d1));
  }
  vec3 d2 = cross(n, d1);

  // Curvature (surface variation, at most 1/3) shortens; a seeded factor varies.
  float len = base_len;
  if (u_has_curvature != 0 && u_curvature_length > 0.0) {
    // Surface variation: ~0 on smooth surfaces, ~0.05 and more at creases
    // and corners (where strokes get their shortest: 15 % of the length).
    float c = curvature[index];
    len *= 1.0 - 0.85 * u_curvature_length * clamp((c == c ? c : 0.0) / 0.05, 0.0, 1.0);
  }
  len *= max(1.0 + u_length_jitter * (2.0 * id_rand(id, 3u, u_seed) - 1.0), 0.05);

  vec3 center = v.xyz;
  if (u_position_jitter > 0.0)
    center += (d1 * (id_rand(id, 6u, u_seed) - 0.5) + d2 * (id_rand(id, 7u, u_seed) - 0.5)) * u_position_jitter * len;

  // Colour: constant, X-Toon, or the point's blended with X-Toon.
  vec3 color = u_constant_color.rgb;
  if (u_coloring == 1) color = tone.rgb;
  if (u_coloring == 2) {
    vec3 pc = source_color(index).rgb;
    color = mix(pc, pc * tone.rgb, u_point_blend);
  }
  color = clamp(color, 0.0, 1.0);
  if (u_hue_shift != 0.0) {
    vec3 hsv = rgb_to_hsv(color);
    color = hsv_to_rgb(vec3(fract(hsv.x + u_hue_shift), hsv.y, hsv.z));
  }
  if (u_pencil_count > 0) color = quantize(color, id);

  // Opacity: pressure follows the X-Toon alpha, with a seeded variation.
  float alpha = u_opacity * mix(1.0, alpha_tex, u_alpha_modification) *
                (1.0 - u_alpha_jitter * id_rand(id, 4u, u_seed));
  if (alpha <= 0.0) {
    return false;
  }
  s.center_alpha = vec4(center, alpha);
  s.d1_length = vec4(d1, len);
  s.n_width = vec4(n, crossing ? -width : width);
  s.color = color;
  return true;
}

// Records are compacted per workgroup in point order (a prefix sum in
// shared memory), each workgroup issuing one indirect draw of its records:
// only surviving strokes reach the rasterizer, in an order that never
// depends on timing.
shared uint s_scan[128];

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint lid = gl_LocalInvocationID.x;
  Stroke s;
  bool alive = i < u_count && place_stroke(i, s);
  s_scan[lid] = alive ? 1u : 0u;
  barrier();
  for (uint offset = 1u; offset < 128u; offset <<= 1u) {
    uint before = lid >= offset ? s_scan[lid - offset] : 0u;
    barrier();
    s_scan[lid] += before;
    barrier();
  }
  uint base = u_out_base + gl_WorkGroupID.x * 128u;
  if (alive) {
    strokes[base + s_scan[lid] - 1u] = s;
    atomicAdd(kept, 1u);
    if (s.n_width.w < 0.0) atomicAdd(crossed, 1u);
  }
  if (lid == 127u) commands[u_command_base + gl_WorkGroupID.x] = DrawCommand(12u * s_scan[127], 1u, 12u * base, 0u);
}
