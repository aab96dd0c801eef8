// The feature_strokes mark's per-point kernel, written once for the GL
// select pass (feature_strokes_select.comp) and the native one
// (cpp/marks/feature_strokes/native.cpp), in the subset of cpp/core/glsl.h.
// The includer defines what reads the point data: point_degree(i),
// has_lines(), point_line(i), point_link(i), point_link_length(i) (the
// FeatureLine attribute's three words), point_resolution(i), inv_median_r(),
// max_r() (the chunk's largest r: FeatureStrokeSettings::max_r),
// has_color(), point_color(i), view_rotation(), lit() (the chunk is
// shaded), point_normal(i) (view space, zero: none), has_opacity() and
// point_opacity(i) (opacity_draws: a Gaussian splat's opacity).
#ifndef FEATURE_STROKES_KERNELS_GLSL
#define FEATURE_STROKES_KERNELS_GLSL
#include "id_hash.glsl"
#include "sparse_growth.glsl"
#include "feature_strokes_settings.glsl"

// Whether point `index` links to a parent in a chain that draws (chain_lines
// on where it applies; its link's flags: render/attributes.h kFeatureChainLinked).
bool draws_link(uint index) {
  return u.chain_lines != 0 && has_lines() && ((point_link(index) >> 24) & 4u) != 0u;
}

// A point's spacing, capped at twice the cloud's sparse spacing (an
// outlier's stays its neighbourhood's); NaN where it has none.
float capped_resolution(uint index) {
  float r = point_resolution(index);
  return r == r ? min(r, max_r()) : r;
}

// A point's share of the surface on screen (px^2): its spacing squared on
// screen (r as the seed's range-aware dithering uses it), foreshortened by
// its normal (at most 5x: a grazing surface).
float surface_px(uint index, vec4 v, float r) {
  float wd = u.ortho != 0 ? 1.0f : -v.z;
  float r_px = (r == r ? r : 0.0f) * u.px_per_unit / wd;
  // Normals only where the chunk is lit (bound): else native has none and GL's binding holds positions.
  vec3 n = lit() ? point_normal(index) : vec3(0.0f);
  float to_eye = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  float facing = n.x * n.x + n.y * n.y + n.z * n.z > 0.25f && to_eye > 0.0f
                     ? abs(n.x * v.x + n.y * v.y + n.z * v.z) / to_eye : 1.0f;
  return r_px * r_px * max(facing, 0.2f);
}

// What point `index` (id `id`, at view position v) draws (seed 001
// sections 5.2, 5.3, 6.2, 6.3); primitive 0: nothing. A point past the
// queue's drawn ones (not `queued`) draws its chain's link or nothing.
Record place_record(uint index, uint id, vec4 v, bool queued) {
  Record rec;
  rec.center_kind = vec4(0.0f);
  rec.dir_length = vec4(0.0f);
  rec.color = vec4(0.0f);
  rec.point_id = id;
  rec.primitive = 0u;
  rec.width = 0.0f;
  rec.chain = 0.0f;
  if (!queued && !draws_link(index)) return rec;
  float depth = -v.z;
  if (!(depth >= u.near_plane && depth <= u.far_plane)) return rec;
  // A Gaussian splat's opacity is its chance of a stroke (opacity_draws),
  // drawn by the hash and salt of points.glsl's kOpacitySalt: the splats
  // the points mark draws; a capture's faint haze gets few.
  if (has_opacity() && !(id_rand(id, 0x6f706163u, 0u) < point_opacity(index))) return rec;
  float fd = point_degree(index);
  bool feature = fd == fd && fd > u.threshold;
  vec4 color = point_color(index);
  uint kind;
  vec3 dir = vec3(0.0f);
  float grow = 1.0f;  // the dithering mark's size: with a tone, larger where the points are too sparse
  float weight = 1.0f;  // a feature primitive's width: with a line tone, thinner in the light
  if (feature) {
    kind = 1u;
    // Line weight from the light (lit chunks): the width times
    // mix(1, 2 (1 - the tone of white under the light), line_tone), as
    // dither_tone raises the dithering's odds; at least a fifth.
    if (lit() && u.line_tone > 0.0f) {
      float shade = diffuse_shaded(vec3(1.0f), point_normal(index), vec3(u.light_dir), u.shading_strength).x;
      weight = max(1.0f + u.line_tone * (2.0f * (1.0f - shade) - 1.0f), 0.2f);
    }
    if (u.use_lines != 0 && has_lines()) {
      uint line_bits = point_line(index);
      float err = float(line_bits >> 24) / 255.0f;
      vec3 d = vec3(unpackSnorm4x8(line_bits));
      // A point of a chain (its link's flags) is on a line whatever its own fit's error.
      bool chained = draws_link(index);
      if (dot(d, d) > 0.25f && (err < u.line_error || chained)) {
        kind = 0u;
        dir = normalize(view_rotation() * d);
      }
    }
    // A rough surface (foliage, a noisy wall) is feature points through and
    // through, with no dithering to give it tone: where its points lie
    // sparser on screen than the tone's ink needs, its marks grow (to 3x),
    // as the dithering's; the line tone then lights them.
    if (kind == 1u && u.tone > 0.0f) {
      float r = capped_resolution(index);
      float need = u.tone * surface_px(index, v, r) / u.other_area;
      grow = sparse_growth(need);
    }
  } else {
    // Range-aware dithering for unorganised clouds: odds by the point's
    // share of surface (its spacing squared, relative to the cloud's median)
    // so the kept points are uniform in 3D, raised where the colour is dark.
    float r = capped_resolution(index);
    float rel = r == r ? r * inv_median_r() : 1.0f;
    float lum = has_color() ? dot(vec3(color), vec3(0.2126f, 0.7152f, 0.0722f)) : 0.5f;
    // Lit (shading): the tone of the colour, or of white, under the light.
    if (lit())
      lum = diffuse_shaded(vec3(has_color() ? lum : 1.0f), point_normal(index), vec3(u.light_dir), u.shading_strength).x;
    float odds = u.dither * rel * rel * mix(1.0f, 2.0f * (1.0f - lum), u.dither_tone);
    if (u.tone > 0.0f) {
      // Kept uniform in 3D, the dithering's ink follows how densely the
      // points lie on screen (a dense statue goes grey all over, a far tile
      // white). With a tone its marks cover tone x (1 - the point's tone)
      // of the surface's area on screen wherever it lies: the odds are that
      // area over a mark's, the point's share of the surface its spacing
      // squared on screen, foreshortened by the normal (r as the seed's
      // range-aware dithering uses it).
      odds = u.tone * (1.0f - lum) * surface_px(index, v, r) / u.dither_area;
      // Where one mark per point is too little ink, each grows (to 3x).
      grow = sparse_growth(odds);
    }
    if (id_rand(id, 1u, u.seed) >= odds) return rec;
    kind = 2u;
  }
  int prim = kind == 0u ? u.prim_directional : kind == 1u ? u.prim_other : u.prim_dither;
  if (prim == 0 || u.opacity <= 0.0f) return rec;
  float len = kind == 0u ? u.directional_length : u.other_length;
  float width = prim == 3 ? u.stroke_width : u.line_width;
  if (prim == 1) {
    len = u.sprite_size;
    width = u.sprite_size;
  }
  len = len * grow;
  width = width * grow * weight;
  vec3 center = vec3(v);
  // A chained directional point (FeatureLine's link, geometry/feature_chains.h)
  // draws the link to its parent, half its width longer at each end so the
  // links of a chain join at any angle: its edge reads as one line, not a
  // tick per point. A link longer on screen than twice the stroke (a
  // close-up) keeps the point's own stroke, so no mark reaches farther than
  // extent() allows.
  if (kind == 0u && prim != 1 && draws_link(index)) {
    uint link = point_link(index);
    vec3 to_parent = view_rotation() * (vec3(unpackSnorm4x8(link)) * point_link_length(index));
    vec3 parent = vec3(v) + to_parent;
    vec4 ca = mat_vec(u.projection, vec4(vec3(v), 1.0f));
    vec4 cb = mat_vec(u.projection, vec4(parent, 1.0f));
    vec2 d = (vec2(cb.x, cb.y) / cb.w - vec2(ca.x, ca.y) / ca.w) * 0.5f * vec2(float(u.size_x), float(u.size_y));
    float seg = sqrt(dot(d, d));
    if (-parent.z >= u.near_plane && seg <= 2.0f * u.directional_length && dot(to_parent, to_parent) > 0.0f) {
      center = 0.5f * (vec3(v) + parent);
      dir = normalize(to_parent);
      width = max(width, 1.5f);  // a line thinner than a pixel breaks into dots
      len = seg + width;
      rec.chain = 1.0f + float((link >> 24) & 3u);  // which ends are free (feature_strokes_sprite.glsl)
    }
  }
  if (!queued && rec.chain == 0.0f) return rec;  // (a link that did not draw: the point's own mark is the queue's)
  rec.center_kind = vec4(center, float(kind));
  rec.dir_length = vec4(dir, len);
  rec.color = vec4(clamp(u.point_coloring != 0 ? vec3(color) : vec3(u.constant_color), 0.0f, 1.0f), u.opacity);
  rec.primitive = uint(prim);
  rec.width = width;
  return rec;
}

#endif
