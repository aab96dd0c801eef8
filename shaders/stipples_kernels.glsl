// The stipples mark's per-point and per-pixel kernels, written once for the
// GL passes (stipples.comp) and the native ones (cpp/marks/stipples/
// native.cpp) in the subset of cpp/core/glsl.h. The includer defines what
// reads the pass's images: hp_at(i) (the spread depth's bits of fine texel
// i), quad_at(i) (the light quadtree), eye_count_at(i), eye_cover_at(i) and
// light_count_at(i).
#ifndef STIPPLES_KERNELS_GLSL
#define STIPPLES_KERNELS_GLSL
#include "id_hash.glsl"
#include "sparse_growth.glsl"
#include "stipples_settings.glsl"

float hash01(uint id, uint salt) { return id_rand(id, salt, u.seed); }

// Monotonic float -> uint (any sign).
uint order_key(float f) {
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

// floor(v) clamped to [lo, hi] as an int, for any v (far outside, NaN: lo).
int floor_clamp(float v, int lo, int hi) {
  float f = floor(v);
  if (!(f >= float(lo))) return lo;
  return f > float(hi) ? hi : int(f);
}

struct Pt {
  vec3 view;
  vec2 center;   // frame pixels
  float depth;   // linear view depth
  ivec2 fine;    // texel of the window's fine texture (0 unless inside)
  bool inside;   // within the clip depths and the window's fine texture
  bool in_depth; // within the clip depths
};

Pt project(vec3 position, mat4 view_from_chunk) {
  Pt p;
  p.view = vec3(mat_vec(view_from_chunk, vec4(position, 1.0f)));
  p.depth = -p.view.z;
  vec4 c = mat_vec(u.projection, vec4(p.view, 1.0f));
  p.center = vec2((c.x / c.w * 0.5f + 0.5f) * float(u.frame_px.x), (c.y / c.w * 0.5f + 0.5f) * float(u.frame_px.y));
  p.in_depth = p.depth >= u.near_plane && p.depth <= u.far_plane;
  // Compared as floats: a point far off screen never overflows an int.
  float fx = floor(p.center.x * u.factor) - float(win.fine_min.x);
  float fy = floor(p.center.y * u.factor) - float(win.fine_min.y);
  p.inside = p.in_depth && c.w > 0.0f && fx >= 0.0f && fy >= 0.0f && fx < float(win.fine_size.x) &&
             fy < float(win.fine_size.y);
  p.fine = p.inside ? ivec2(int(fx), int(fy)) : ivec2(0);
  return p;
}

uint fine_index(ivec2 t) { return uint(t.y) * uint(win.fine_size.x) + uint(t.x); }
// Whether the window counts a frame texel's points for the frame.
bool owned_texel(ivec2 t) {
  return t.x >= win.owned_min.x && t.y >= win.owned_min.y && t.x < win.owned_max.x && t.y < win.owned_max.y;
}
bool owned(Pt p) { return owned_texel(p.fine + win.fine_min); }
// spread_from_spacing: how many fine texels a point covers around it before
// the iterations: half its own spacing on screen (`scale`: half the texels
// per scene unit at view depth 1), so the points of a sparse surface meet
// and hide what lies behind it, and the surface is counted whole for the
// tone. The spacing is taken at most `cap` (the scan's sparse spacing): a
// gap wider than nine in ten of the scan's points have around them is a
// hole in the scan, and a lone point stays small. At most u.spread_max
// texels, which bounds a point's work and the tiles' halos.
int spread_texels(float depth, float spacing, float cap, float scale) {
  if (u.spread_max <= 0) return 0;
  float t = min(spacing, cap) * scale;
  return floor_clamp(u.ortho != 0 ? t : t / depth, 0, u.spread_max);
}
// Whether a texel (dx, dy) from the point's lies within its spread r: a
// disc, as the point's share of the surface is.
bool in_spread(int dx, int dy, int r) { return dx * dx + dy * dy <= r * r + r; }
// The depth a point writes `ring` texels from its own (Chebyshev): a step
// deeper per texel, as that many spreading passes would give it.
float spread_depth(Pt p, int ring) { return p.depth + u.offset * float(ring); }

// Not behind the spread surface: within one step of its texel's depth.
bool hp_visible(Pt p) { return p.inside && p.depth <= uintBitsToFloat(hp_at(fine_index(p.fine))) + u.offset; }

// Dot products written out: llvmpipe's dot() rounds otherwise than GLM's.
vec2 light_uv(vec3 v) {
  return vec2(((v.x * u.light_right.x + v.y * u.light_right.y + v.z * u.light_right.z) - u.light_origin.x) / u.light_extent,
              ((v.x * u.light_up.x + v.y * u.light_up.y + v.z * u.light_up.z) - u.light_origin.y) / u.light_extent);
}
// Distance from the light (smaller: closer to it).
uint light_key(vec3 v) { return order_key(-(v.x * u.light_dir.x + v.y * u.light_dir.y + v.z * u.light_dir.z)); }
ivec2 light_texel(vec3 v, int level) {
  int side = 1 << level;
  vec2 uv = light_uv(v);
  return ivec2(floor_clamp(uv.x * float(side), 0, side - 1), floor_clamp(uv.y * float(side), 0, side - 1));
}
// Level l of the quadtree texture: x from 2^(n+1) - 2^(l+1), width 2^l.
uint quad_index(ivec2 t, int level) {
  int x0 = (2 << u.levels) - (2 << level);
  return uint(t.y) * uint(2 << u.levels) + uint(x0 + t.x);
}
// The eye cell along one axis of a position in frame pixels.
int eye_axis(float pixel, int eye_min, int cells) {
  return floor_clamp(floor(pixel / u.eye_cell) - float(eye_min), 0, cells - 1);
}
uint eye_index(vec2 center) {
  return uint(eye_axis(center.y, win.eye_min.y, win.eye_cells.y)) * uint(win.eye_cells.x) +
         uint(eye_axis(center.x, win.eye_min.x, win.eye_cells.x));
}
uint light_cell_index(vec3 v) {
  vec2 uv = light_uv(v);
  int n = u.light_cells;
  return uint(floor_clamp(uv.y * float(n), 0, n - 1)) * uint(n) + uint(floor_clamp(uv.x * float(n), 0, n - 1));
}
// Overlap of cell [c, c + 1) with the window [lo, hi) (cell units).
float overlap(float c, float lo, float hi) { return clamp(min(c + 1.0f, hi) - max(c, lo), 0.0f, 1.0f); }

// The visible points (x) and covered fine texels (y) of the eye cells within
// 1.5 cells of a frame pixel position, each cell weighted by its overlap
// with that window, so they vary continuously as the position moves over
// the cells (whole cells would jump at every cell edge as the camera moves).
// In the frame's cells, so every window (tile) weighs them with the same floats.
vec2 eye_sums(vec2 center) {
  vec2 e = vec2(center.x / u.eye_cell, center.y / u.eye_cell);
  ivec2 e0 = ivec2(int(floor(e.x - 1.5f)), int(floor(e.y - 1.5f)));
  float ox[4];
  float oy[4];
  for (int k = 0; k <= 3; ++k) {
    ox[k] = overlap(float(e0.x + k), e.x - 1.5f, e.x + 1.5f);
    oy[k] = overlap(float(e0.y + k), e.y - 1.5f, e.y + 1.5f);
  }
  float points = 0.0f, covered = 0.0f;
  for (int dy = 0; dy <= 3; ++dy)
    for (int dx = 0; dx <= 3; ++dx) {
      ivec2 c = ivec2(e0.x + dx - win.eye_min.x, e0.y + dy - win.eye_min.y);
      if (c.x < 0 || c.y < 0 || c.x >= win.eye_cells.x || c.y >= win.eye_cells.y) continue;
      float w = ox[dx] * oy[dy];
      uint i = uint(c.y) * uint(win.eye_cells.x) + uint(c.x);
      points += w * float(eye_count_at(i));
      covered += w * float(eye_cover_at(i));
    }
  return vec2(points, covered);
}

// The light plane's area per visible point around a point: a surface of
// area a per point shows a |n.l| of it to the light. Scene units^2, over a
// window 3 light cells wide centred on the point, each cell weighted by its
// overlap with it.
float light_area(Pt p) {
  float ox[4];
  float oy[4];
  vec2 l = light_uv(p.view) * float(u.light_cells);
  ivec2 l0 = ivec2(int(floor(l.x - 1.5f)), int(floor(l.y - 1.5f)));
  for (int k = 0; k <= 3; ++k) {
    ox[k] = overlap(float(l0.x + k), l.x - 1.5f, l.x + 1.5f);
    oy[k] = overlap(float(l0.y + k), l.y - 1.5f, l.y + 1.5f);
  }
  float lpoints = 0.0f, occupied = 0.0f;
  for (int dy = 0; dy <= 3; ++dy)
    for (int dx = 0; dx <= 3; ++dx) {
      ivec2 c = ivec2(l0.x + dx, l0.y + dy);
      if (c.x < 0 || c.y < 0 || c.x >= u.light_cells || c.y >= u.light_cells) continue;
      float w = ox[dx] * oy[dy];
      uint n = light_count_at(uint(c.y) * uint(u.light_cells) + uint(c.x));
      lpoints += w * float(n);
      occupied += n > 0u ? w : 0.0f;
    }
  float cell = u.light_extent / float(u.light_cells);
  return occupied * cell * cell / max(lpoints, 1.0f);
}

// order_key's float.
float key_value(uint k) { return uintBitsToFloat((k & 0x80000000u) != 0u ? k & 0x7fffffffu : ~k); }

// A point's normal (snorm8 in chunk space, point_attributes.glsl's) in view
// space, unit (zero: none), written out so both backends round alike. The
// view's own matrix turns it: exact for rotations and uniform scales, the
// transforms scans are placed with.
vec3 packed_view_normal(uint bits, mat4 view_from_chunk) {
  vec4 n = unpackSnorm4x8(bits);
  PRECISE vec4 v = mat_vec(view_from_chunk, vec4(n.x, n.y, n.z, 0.0f));
  PRECISE float len = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return len > 0.0f ? vec3(v.x / len, v.y / len, v.z / len) : vec3(0.0f);
}

// How much of a point's dot the light leaves (diffuse): 1 whole, 0 none.
// Its cell of the diffuse LEVEL (the finer level with probability frac) in
// the light-view quadtree; with the level from the spacing, the level whose
// cells are `cell_target` wide (its own spacing, scaled by LEVEL): between
// two levels' widths, the finer with the share of the way to it.
// nearest (the paper's): the caster closest to the light in the cell stays
// paper. A surface facing the light holds about one point per cell, so the
// share hidden follows N.L; but which point is nearest changes as the
// cells of a light that turns with the camera slide over the points.
// share: a point the light reaches (with cast shadows, no farther from it
// than its cell's nearest plus the visibility step: the eye's rule, seen
// from the light) is hidden with the chance the nearest rule gives on
// average, its N.L times u.share_scale (n: its normal in view space,
// packed_view_normal, turned toward the eye), against a number fixed per
// point, so the same dots stay as the light turns; its dot shrinks over
// the last fifth of that chance before it goes, so a moving light fades
// dots instead of popping them.
float lit_scale(Pt p, uint id, float cell_target, vec3 n) {
  if (u.quadtree != 0) {
    int level = u.level_lo;
    float frac = u.level_frac;
    if (u.level_from_spacing != 0) {
      float cell = u.light_extent;
      level = 0;
      while (level < u.levels && 0.5f * cell >= cell_target) {
        cell = 0.5f * cell;
        level += 1;
      }
      frac = level < u.levels ? clamp(2.0f - 2.0f * cell_target / cell, 0.0f, 1.0f) : 0.0f;
    }
    level += hash01(id, 1u) < frac ? 1 : 0;
    // The share's shadows one level coarser: cells twice as wide hold a
    // caster wherever a nearer surface is about as dense as the lit one.
    if (u.lit_share != 0) level = max(level - 1, 0);
    ivec2 t = light_texel(p.view, u.levels) >> (u.levels - level);
    uint nearest = quad_at(quad_index(t, level));
    uint key = light_key(p.view);
    if (u.lit_share == 0) return nearest == key ? 0.0f : 1.0f;
    if (!(key_value(key) <= key_value(nearest) + u.offset)) return 1.0f;  // in the shadow of nearer casters
  }
  PRECISE float toward_eye = u.ortho != 0 ? n.z : -(n.x * p.view.x + n.y * p.view.y + n.z * p.view.z);
  PRECISE float nl = n.x * u.light_dir.x + n.y * u.light_dir.y + n.z * u.light_dir.z;
  float share = max(toward_eye < 0.0f ? -nl : nl, 0.0f) * u.share_scale;
  if (u.specular != 0) {
    // The highlight, where the normal (turned toward the eye) nears the
    // half-way vector H of light and eye: hidden as specular_out hides, with
    // 1 - N.H as the difference from the brightest (the paper's measure,
    // counted on the eye and light planes, finds no highlight on a real scan).
    PRECISE float vlen = sqrt(p.view.x * p.view.x + p.view.y * p.view.y + p.view.z * p.view.z);
    vec3 eye = u.ortho != 0 ? vec3(0.0f, 0.0f, 1.0f) : vec3(-p.view.x / vlen, -p.view.y / vlen, -p.view.z / vlen);
    PRECISE vec3 h = vec3(u.light_dir.x + eye.x, u.light_dir.y + eye.y, u.light_dir.z + eye.z);
    PRECISE float hlen = sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
    PRECISE float nh = (n.x * h.x + n.y * h.y + n.z * h.z) / max(hlen, 1e-20f);
    share += clamp(1.0f - (1.0f - (toward_eye < 0.0f ? -nh : nh)) / max(u.tau, 1e-6f), 0.0f, 1.0f);
  }
  return clamp((hash01(id, 7u) - share) * 5.0f + 1.0f, 0.0f, 1.0f);
}

// Area per point on the eye and light planes around a point: a surface of
// a points per unit area shows a (n.v) and a (n.l) there, so their sum
// grows with n.(v + l): largest where the surface faces the half-way
// direction of eye and light (the highlight). Scene units^2. Both sums run
// over a window 3 cells wide centred on the point (eye_sums, light_area).
float specular_raw(Pt p) {
  vec2 sums = eye_sums(p.center);
  float points = sums.x, covered = sums.y;
  float wd = u.ortho != 0 ? 1.0f : p.depth;
  float px_area = wd / u.px_per_unit;
  float eye_area = covered / (u.factor * u.factor) * px_area * px_area / max(points, 1.0f);
  return eye_area + light_area(p);
}

// The specular measure: specular_raw, or with the level from the spacing
// over the square of the point's cell target (its own spacing, scaled
// alike for the frame), so it is the area per point on the eye and light
// planes per unit of the point's own surface: n.(v + l) wherever the scan
// is denser or sparser. Raw, the sparser parts of a scan read as the
// highlight (they show more area per point from anywhere).
float specular_measure(Pt p, float cell_target) {
  float raw = specular_raw(p);
  return u.level_from_spacing != 0 && cell_target > 0.0f ? raw / (cell_target * cell_target) : raw;
}

// The histogram of specular_raw: 8 bins per octave of 2^-64 .. 2^64, the
// octave from the exponent, the bin within it by the mantissa against
// 2^(k/8) (float bits). Exact, unlike log2 (llvmpipe's approximates it).
float bin_edge(int k) {
  return uintBitsToFloat(k == 0 ? 0x3f8b95c2u : k == 1 ? 0x3f9837f0u : k == 2 ? 0x3fa5fed7u : k == 3 ? 0x3fb504f3u :
                         k == 4 ? 0x3fc5672au : k == 5 ? 0x3fd744fdu : 0x3feac0c7u);
}
int specular_bin(float s) {
  uint b = floatBitsToUint(max(s, 1e-30f));
  int octave = int(b >> 23) - 127;
  float mantissa = uintBitsToFloat((b & 0x007fffffu) | 0x3f800000u);
  int within = 0;
  for (int k = 0; k < 7; ++k) within += mantissa >= bin_edge(k) ? 1 : 0;
  return clamp((octave + 64) * 8 + within, 0, 1023);  // kStippleHistogramBins - 1
}
// Hidden with probability 1 - diff / tau, diff the point's distance below
// the segment's reference (a high percentile of specular_raw).
bool specular_out(uint id, float raw, float spec_ref) { return 1.0f - raw / spec_ref < u.tau * hash01(id, 2u); }

// 1 + jitter * (2h - 1), written as the GL compiler (NIR) reassociates it,
// so both backends round alike.
float dot_diameter(uint id) {
  return max(u.dot_size * ((1.0f - u.size_jitter) + 2.0f * u.size_jitter * hash01(id, 3u)), 0.5f);
}

// Seed 003 draws a dot per visible point, so its ink follows how densely
// the scan's points lie on screen: a dense statue goes black, an aerial
// tile stays white, and the tone changes with the output size. With a
// tone, dots cover about that share of an unlit surface (dots placed at
// random cover 1 - exp(-dots per pixel x dot area)) at any density: where
// the visible points crowd, a share of them draws (chosen by the point id,
// so the same dots stay as the camera moves); where they are sparse, each
// dot grows, up to 3 times its diameter (larger reads as blots, not dots).
// The lit thinning then takes its share of those. And as scans sample in
// rows (scan lines, sensor grids), each dot moves within its point's own
// share of the surface (a square as wide as their spacing on screen, at
// most 3 dot sizes), so the dots scatter as a stipple artist's do, not in
// the scanner's rows.
struct Dot {
  vec2 center;     // frame pixels
  float diameter;  // 0: none
};
Dot tone_dot(Pt p, uint id) {
  Dot dot;
  dot.center = p.center;
  dot.diameter = dot_diameter(id);
  if (u.tone_scale <= 0.0f) return dot;
  vec2 sums = eye_sums(p.center);
  if (!(sums.x > 0.0f)) return dot;
  float pixels_per_point = sums.y / (u.factor * u.factor * sums.x);
  float spacing = min(sqrt(pixels_per_point), 3.0f * u.dot_size);
  dot.center = vec2(p.center.x + spacing * (hash01(id, 5u) - 0.5f), p.center.y + spacing * (hash01(id, 6u) - 0.5f));
  float share = u.tone_scale * pixels_per_point;
  if (share < 1.0f)
    dot.diameter = hash01(id, 4u) < share ? dot.diameter : 0.0f;
  else
    dot.diameter = dot.diameter * sparse_growth(share);
  return dot;
}
// Area coverage of a disc at (dx, dy) from a pixel's centre: a 1 px wide
// antialiased edge, at least a pixel's worth spread over the pixels a small
// dot touches.
float dot_coverage(float dx, float dy, float diameter) {
  float r = 0.5f * diameter;
  return clamp(r + 0.5f - sqrt(dx * dx + dy * dy), 0.0f, 1.0f) * min(1.0f, diameter * diameter);
}

// The fine texel (one axis) under a frame pixel's centre, clamped to the window.
int resolve_texel(int pixel, int axis) {
  float t = floor((float(pixel) + 0.5f) * u.factor);
  return axis == 0 ? floor_clamp(t - float(win.fine_min.x), 0, win.fine_size.x - 1)
                   : floor_clamp(t - float(win.fine_min.y), 0, win.fine_size.y - 1);
}

// A pixel's dots over the paper (where the spread surface covers it).
struct StipplePixel {
  vec4 color;
  float depth;
};
StipplePixel resolve_pixel(float coverage, float dot_depth, float surface) {
  StipplePixel px;
  bool on_surface = !isinf(surface) && u.paper.w > 0.0f;
  float ink = coverage * u.dot_color.w;
  float paper = on_surface ? u.paper.w : 0.0f;
  float alpha = ink + paper * (1.0f - ink);
  float inf = uintBitsToFloat(0x7f800000u);
  if (alpha > 0.0f) {
    vec3 rgb = (vec3(u.dot_color) * ink + vec3(u.paper) * paper * (1.0f - ink)) / alpha;
    px.color = vec4(clamp(rgb, 0.0f, 1.0f), alpha);
    px.depth = ink > 0.0f ? min(dot_depth, on_surface ? surface : inf) : surface;
  } else {
    px.color = vec4(0.0f);
    px.depth = inf;
  }
  return px;
}
#endif
