// The hatching mark's per-point kernels, written once for the GL pass
// (hatching_select.comp) and the native one (cpp/marks/hatching/native.cpp)
// in the subset of cpp/core/glsl.h. The includer defines what reads the
// point data: has_spacing(), point_spacing(i), has_curvature(),
// point_curvature(i), point_color(i), point_color_median() (the cloud's median
// colour luminance, 0 for the constant colour) and xtoon_image(uv).
#ifndef HATCHING_KERNELS_GLSL
#define HATCHING_KERNELS_GLSL
#include "id_hash.glsl"
#include "sparse_growth.glsl"
#include "hatching_settings.glsl"

// The procedural X-Toon textures: x = brightness, y = depth (0 near). As
// the paper's (its Fig. 2) they leave depth unused, so which points draw
// never changes as the camera moves; an image texture may use it.
vec4 xtoon(vec2 uv) {
  float b = uv.x;
  if (u.xtoon == 0)  // pencil: graphite, strokes fade with the light
    return vec4(vec3(0.16f, 0.16f, 0.19f), 1.0f - smoothstep(0.1f, 0.95f, b));
  if (u.xtoon == 1) {  // wax crayon: three bands of tone, warm colours
    float a = b < 0.35f ? 1.0f : b < 0.7f ? 0.6f : 0.22f;
    return vec4(mix(vec3(0.45f, 0.12f, 0.10f), vec3(0.98f, 0.62f, 0.18f), b), a);
  }
  if (u.xtoon == 2)  // two-coloured: cool shadows to warm light
    return vec4(mix(vec3(0.12f, 0.22f, 0.62f), vec3(0.96f, 0.62f, 0.22f), smoothstep(0.0f, 1.0f, b)), 1.0f - 0.75f * b);
  if (u.xtoon == 3)  // chalk: light strokes where lit, for dark paper
    return vec4(vec3(0.95f, 0.95f, 0.9f), smoothstep(0.15f, 0.9f, b));
  if (u.xtoon == 4)  // ink: dark strokes in the shade only
    return vec4(vec3(0.04f, 0.04f, 0.08f), 1.0f - smoothstep(0.42f, 0.5f, b));
  return xtoon_image(uv);
}

vec3 rgb_to_hsv(vec3 c) {
  float mx = max(c.r, max(c.g, c.b)), mn = min(c.r, min(c.g, c.b)), d = mx - mn;
  float h = 0.0f;
  if (d > 0.0f) {
    if (mx == c.r) h = mod((c.g - c.b) / d, 6.0f);
    else if (mx == c.g) h = (c.b - c.r) / d + 2.0f;
    else h = (c.r - c.g) / d + 4.0f;
  }
  return vec3(h / 6.0f, mx > 0.0f ? d / mx : 0.0f, mx);
}
vec3 hsv_to_rgb(vec3 c) {
  vec3 k = clamp(abs(mod(c.x * 6.0f + vec3(0.0f, 4.0f, 2.0f), 6.0f) - 3.0f) - 1.0f, 0.0f, 1.0f);
  return c.z * mix(vec3(1.0f), k, c.y);
}

// Section 3.3: the two pencils whose hues enclose the colour's, one chosen
// with probability by closeness, then mixed with black and white so value
// and saturation match.
vec3 quantize(vec3 c, uint id) {
  vec3 hsv = rgb_to_hsv(c);
  int n = u.pencil_count;
  int hi = 0;
  while (hi < n && u.pencils[hi].w <= hsv.x) ++hi;
  int i1 = (hi + n - 1) % n, i2 = hi % n;
  float h1 = u.pencils[i1].w, h2 = u.pencils[i2].w;
  float span = fract(h2 - h1 + 1.0f), into = fract(hsv.x - h1 + 1.0f);
  float a = span > 0.0f ? clamp(1.0f - into / span, 0.0f, 1.0f) : 1.0f;  // weight of pencil 1
  vec3 pencil = id_rand(id, 5u, u.seed) < a ? vec3(u.pencils[i1]) : vec3(u.pencils[i2]);
  vec3 p = rgb_to_hsv(pencil);
  float chroma = p.y * p.z;
  float kc = chroma > 1e-4f ? clamp(hsv.y * hsv.z / chroma, 0.0f, 1.0f) : 0.0f;
  float kw = clamp(hsv.z - kc * p.z, 0.0f, 1.0f - kc);
  return kc * pencil + vec3(kw);
}

// The strokes of point `index` (id `id`) at view position v with view
// normal n (vec3(0): none usable); center_alpha.w <= 0: it draws none.
Stroke place_stroke(uint index, uint id, vec4 v, vec3 n) {
  Stroke s;
  s.center_alpha = vec4(0.0f);
  s.d1_length = vec4(0.0f);
  s.n_width = vec4(0.0f);
  s.color = vec3(0.0f);
  s.point_id = id;
  float depth = -v.z;
  if (!(depth >= u.near_plane && depth <= u.far_plane)) return s;
  vec3 to_eye = u.ortho != 0 ? vec3(0.0f, 0.0f, 1.0f) : normalize(-vec3(v));
  if (n == vec3(0.0f)) n = to_eye;  // no usable normal: a view-facing stroke
  // Two-sided: turned toward the camera (for clouds whose normals are not
  // consistently oriented; changes at silhouettes as the camera moves).
  else if (u.two_sided != 0 && dot(n, to_eye) < 0.0f) n = -n;

  // X-Toon coordinates: brightness (diffuse + ambient + Phong) and depth.
  vec3 light = vec3(u.light_dir);
  float diffuse = max(dot(n, light), 0.0f);
  // The highlight takes its share from the diffuse term (k_d + k_s = 1):
  // added on top, it falls where the diffuse light already saturates the
  // tone and shows nowhere.
  float lit = diffuse;
  if (u.specular > 0.0f)
    lit = (1.0f - u.specular) * diffuse + u.specular * pow(max(dot(reflect(-light, n), to_eye), 0.0f), u.shininess);
  float brightness = clamp(u.ambient + (1.0f - u.ambient) * lit, 0.0f, 1.0f);
  // A drawing in the scan's colours: a colour darker than the scan's median
  // is darker in the tone, a lighter one lighter (the constant colour of a
  // cloud with none: no change).
  float median = point_color_median();
  if (u.color_tone > 0.0f && median > 0.0f) {
    float value = dot(point_color(index), vec3(0.2126f, 0.7152f, 0.0722f)) / median;
    brightness = clamp(brightness * mix(1.0f, value, u.color_tone), 0.0f, 1.0f);
  }
  float depth01 = clamp((depth - u.depth_min) / max(u.depth_max - u.depth_min, 1e-6f), 0.0f, 1.0f);
  vec4 tone = xtoon(vec2(brightness, depth01));
  float alpha_tex = clamp(tone.a, 0.0f, 1.0f);

  // Length and width in scene units (before the per-stroke variations).
  float scale = u.world_units != 0 ? 1.0f : (u.ortho != 0 ? 1.0f : depth) / u.px_per_unit;
  float full_len = u.stroke_length * scale;
  float width = u.stroke_width * scale;
  // Curvature (surface variation, at most 1/3) shortens the stroke: ~0 on
  // smooth surfaces, ~0.05 and more at creases and corners (where strokes
  // get their shortest: 15 % of the length).
  float shortened = 1.0f;
  if (has_curvature() && u.curvature_length > 0.0f) {
    float c = point_curvature(index);
    shortened = 1.0f - 0.85f * u.curvature_length * clamp((c == c ? c : 0.0f) / 0.05f, 0.0f, 1.0f);
  }
  float base_len = full_len * shortened;

  // Lighting by omission and cross vs parallel, by probabilistic
  // interpolation; the coverage limit scales the odds by the point's share
  // of the surface over a stroke's area (as many strokes per area however
  // dense or irregular the scan). Curvature changes the strokes' length,
  // not the tone: the ink a shortened stroke loses is made up by keeping
  // more strokes where the limit thins them, and the rest by crossing more
  // of them (cross_hatch > 0; one crossing at most).
  float keep = alpha_tex * u.density;
  float crossing_odds = alpha_tex * u.cross_share;
  float ink_kept = shortened;  // of a full-length stroke's, after the limit's share
  if (u.coverage > 0.0f && has_spacing()) {
    float r = point_spacing(index);
    float area = 0.88f * r * r;
    float limit = u.coverage * area / max(full_len * width * (1.0f + crossing_odds), 1e-30f);
    keep *= min(1.0f, limit / shortened);
    // grow_sparse_strokes: where the points are too sparse for the coverage
    // (every stroke drawn still covers the surface fewer times: a near or
    // sparse surface), each stroke grows, length and width alike, at most
    // 3x (as the stipples' dots and the feature strokes' marks do): the
    // tone at any density.
    if (u.grow_sparse != 0) {
      float grow = sparse_growth(limit);
      base_len *= grow;
      width *= grow;
    }
    ink_kept = shortened * min(1.0f, limit / shortened) / max(min(1.0f, limit), 1e-30f);
  }
  // A Gaussian splat's opacity scales the odds (opacity_draws): a capture's
  // faint haze gets few strokes.
  if (has_opacity()) keep *= point_opacity(index);
  if (id_rand(id, 0u, u.seed) >= keep) return s;
  if (crossing_odds > 0.0f && ink_kept < 1.0f) crossing_odds = min(1.0f, (1.0f + crossing_odds) / ink_kept - 1.0f);
  bool crossing = id_rand(id, 1u, u.seed) < crossing_odds;

  // d1 = u - (u.n) n; where u is (nearly) the normal, the axis least aligned with it.
  vec3 line = vec3(u.direction);
  vec3 d1 = line - dot(line, n) * n;
  if (dot(d1, d1) < 1e-6f) {
    vec3 a = abs(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    d1 = a - dot(a, n) * n;
  }
  d1 = normalize(d1);
  if (u.angle_jitter > 0.0f) {
    float t = u.angle_jitter * (2.0f * id_rand(id, 2u, u.seed) - 1.0f);
    d1 = normalize(cos(t) * d1 + sin(t) * cross(n, d1));
  }
  vec3 d2 = cross(n, d1);

  // A seeded factor varies the length.
  float len = base_len * max(1.0f + u.length_jitter * (2.0f * id_rand(id, 3u, u.seed) - 1.0f), 0.05f);

  vec3 center = vec3(v);
  if (u.position_jitter > 0.0f)
    center += (d1 * (id_rand(id, 6u, u.seed) - 0.5f) + d2 * (id_rand(id, 7u, u.seed) - 0.5f)) * u.position_jitter * len;

  // Colour: constant, X-Toon, or the point's blended with X-Toon.
  vec3 color = vec3(u.constant_color);
  if (u.coloring == 1) color = vec3(tone);
  if (u.coloring == 2) {
    vec3 pc = point_color(index);
    color = mix(pc, pc * vec3(tone), u.point_blend);
  }
  color = clamp(color, 0.0f, 1.0f);
  if (u.hue_shift != 0.0f) {
    vec3 hsv = rgb_to_hsv(color);
    color = hsv_to_rgb(vec3(fract(hsv.x + u.hue_shift), hsv.y, hsv.z));
  }
  if (u.pencil_count > 0) color = quantize(color, id);

  // Opacity: pressure follows the X-Toon alpha, with a seeded variation.
  float alpha = u.opacity * mix(1.0f, alpha_tex, u.alpha_modification) *
                (1.0f - u.alpha_jitter * id_rand(id, 4u, u.seed));
  if (alpha <= 0.0f) return s;
  s.center_alpha = vec4(center, alpha);
  s.d1_length = vec4(d1, len);
  s.n_width = vec4(n, crossing ? -width : width);
  s.color = color;
  return s;
}
#endif
