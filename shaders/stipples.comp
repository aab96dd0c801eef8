// Stippling without normals (seed 003; cpp/marks/stipples.cpp): hidden-point
// removal in an enlarged image-space depth texture, diffuse shading by a
// light-view min-depth quadtree, specular highlights from point counts seen
// from the eye and from the light, then dots. Every pass is order-
// independent (integer atomicMin / atomicMax / atomicAdd) and every random
// choice hashes the point id.
// variants: PASS_PROJECT | PASS_DILATE | PASS_ERODE | PASS_VISIBLE | PASS_COVER | PASS_REDUCE | PASS_SPECULAR | PASS_DRAW | PASS_RESOLVE
#include "common.glsl"
#include "point_attributes.glsl"

#if defined(PASS_DILATE) || defined(PASS_ERODE) || defined(PASS_COVER) || defined(PASS_REDUCE) || defined(PASS_RESOLVE)
layout(local_size_x = 16, local_size_y = 16) in;
#else
layout(local_size_x = 128) in;
#endif

layout(std430, binding = 3) buffer HiddenPoints { uint hp[]; };      // fine eye texture: depth bits, +inf empty
layout(std430, binding = 4) buffer HiddenPointsOut { uint hp_out[]; };  // PASS_VISIBLE, PASS_RESOLVE: the visible surface
layout(std430, binding = 5) buffer Quadtree { uint quad[]; };        // levels 0..n in one 2^(n+1) x 2^n texture
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 7) buffer EyeCount { uint eye_count[]; };   // visible points per eye cell
layout(std430, binding = 8) buffer EyeCover { uint eye_cover[]; };   // covered fine texels per eye cell
layout(std430, binding = 9) buffer LightCount { uint light_count[]; };  // visible points per light cell
layout(std430, binding = 10) buffer DotCoverage { uint dot_cov[]; }; // per clip pixel, float bits (max)
layout(std430, binding = 11) buffer DotDepth { uint dot_depth[]; };  // per clip pixel, float bits (min)
layout(std430, binding = 12) buffer Globals { uint spec_total; uint visible_count; uint kept_count; uint captured; };
layout(std430, binding = 14) buffer SpecularHistogram { uint spec_hist[]; };  // log2 bins, 8 per octave
layout(std430, binding = 15) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices (u_queue)
uniform int u_queue;  // 1: invocation i takes the chunk's i-th point of the resolution queue
struct Captured { vec4 center_id; };  // view-space centre, point id (bits)
layout(std430, binding = 13) writeonly buffer Capture { Captured capture[]; };
#ifdef PASS_RESOLVE
layout(rgba32f, binding = 0) uniform writeonly image2D u_color_out;
layout(r32f, binding = 1) uniform writeonly image2D u_depth_out;
#endif

uniform mat4 u_projection;
uniform ivec2 u_size;          // the frame's (positions below are frame pixels; images are local: - u_origin)
uniform float u_near;
uniform float u_far;
uniform int u_ortho;
uniform float u_px_per_unit;   // pixels per scene unit at view depth 1
uniform ivec2 u_clip_min;      // local pixels
uniform ivec2 u_clip_max;
uniform float u_factor;        // fine texels per pixel
// The fine texture's (0, 0) is the frame's fine texel u_fine_min: texels
// are anchored at the frame's corner, not at the segment's rectangle (which
// moves with the camera and with the tile).
uniform ivec2 u_fine_min;
uniform ivec2 u_fine_size;
// Frame texels whose points this window counts for the frame (visible
// count, light cells, visible casters, the specular histogram): each point
// in one window's, whichever windows the frame is cut into.
uniform ivec2 u_owned_min;
uniform ivec2 u_owned_max;
uniform int u_project_hp;      // PASS_PROJECT: into the fine texture
uniform int u_project_quad;    // PASS_PROJECT: every caster into the quadtree
uniform int u_accumulate;      // PASS_VISIBLE: the frame's counts of the owned points
uniform float u_offset;        // depth added per spreading step, scene units
uniform int u_casters_all;     // 1: every point casts into the light quadtree, 0: visible points only
// Light: orthographic, along u_light_dir (towards the light, view space).
uniform vec3 u_light_dir;
uniform vec3 u_light_right;
uniform vec3 u_light_up;
uniform vec2 u_light_origin;   // (right, up) of the light texture's corner
uniform float u_light_extent;  // side of the light texture, scene units
uniform int u_levels;          // n: level n is 2^n x 2^n texels
uniform int u_reduce_level;    // PASS_REDUCE: the level written
uniform int u_diffuse;
uniform int u_level_lo;
uniform float u_level_frac;
uniform int u_specular;
uniform float u_tau;
uniform float u_spec_ref;      // PASS_DRAW: the segment's high percentile of specular_raw
uniform float u_eye_cell;      // pixels
uniform ivec2 u_eye_min;       // the first eye cell (frame-anchored, like the fine texels)
uniform ivec2 u_eye_cells;
uniform int u_light_cells;     // per side
uniform float u_dot_size;
uniform float u_size_jitter;
uniform uint u_seed;
uniform int u_capture;
uniform vec4 u_dot_color;
uniform vec4 u_paper;

float hash01(uint id, uint salt) {
  return float(hash_u32(id ^ hash_u32(salt * 0x9e3779b9u + u_seed * 0x85ebca6bu)) >> 8) * (1.0 / 16777216.0);
}

// Monotonic float -> uint (any sign).
uint order_key(float f) {
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

struct Pt {
  vec3 view;
  vec2 center;  // frame pixels
  float depth;  // linear view depth
  ivec2 fine;   // texel of the fine eye texture
  bool inside;  // in the clip range and the clip rect
};

Pt project(uint index) {
  Pt p;
  p.view = (u_view_from_chunk * vec4(point_position(index), 1.0)).xyz;
  p.depth = -p.view.z;
  vec4 c = u_projection * vec4(p.view, 1.0);
  p.center = (c.xy / c.w * 0.5 + 0.5) * vec2(u_size);
  p.fine = ivec2(floor(p.center * u_factor)) - u_fine_min;
  p.inside = p.depth >= u_near && p.depth <= u_far && c.w > 0.0 && all(greaterThanEqual(p.fine, ivec2(0))) &&
             all(lessThan(p.fine, u_fine_size));
  return p;
}

uint fine_index(ivec2 t) { return uint(t.y) * uint(u_fine_size.x) + uint(t.x); }
bool owned(Pt p) {
  ivec2 t = p.fine + u_fine_min;
  return all(greaterThanEqual(t, u_owned_min)) && all(lessThan(t, u_owned_max));
}

// Not behind the spread surface: within one step of its texel's depth.
bool hp_visible(Pt p) { return p.inside && p.depth <= uintBitsToFloat(hp[fine_index(p.fine)]) + u_offset; }

vec2 light_uv(vec3 v) {
  return (vec2(dot(v, u_light_right), dot(v, u_light_up)) - u_light_origin) / u_light_extent;
}
// Distance from the light (smaller: closer to it).
uint light_key(vec3 v) { return order_key(-dot(v, u_light_dir)); }
ivec2 light_texel(vec3 v, int level) {
  int side = 1 << level;
  return clamp(ivec2(floor(light_uv(v) * float(side))), ivec2(0), ivec2(side - 1));
}
// Level l of the quadtree texture: x from 2^(n+1) - 2^(l+1), width 2^l.
uint quad_index(ivec2 t, int level) {
  int x0 = (2 << u_levels) - (2 << level);
  return uint(t.y) * uint(2 << u_levels) + uint(x0 + t.x);
}

ivec2 eye_cell(vec2 center) {
  return clamp(ivec2(floor(center / u_eye_cell)) - u_eye_min, ivec2(0), u_eye_cells - 1);
}
ivec2 light_cell(vec3 v) {
  return clamp(ivec2(floor(light_uv(v) * float(u_light_cells))), ivec2(0), ivec2(u_light_cells - 1));
}
// Overlap of cell [c, c + 1) with the window [lo, hi) (cell units).
float overlap(float c, float lo, float hi) { return clamp(min(c + 1.0, hi) - max(c, lo), 0.0, 1.0); }

// Area per point on the eye and light planes around a point (3 x 3 cells):
// a surface of a points per unit area shows a (n.v) and a (n.l) there, so
// their sum grows with n.(v + l): largest where the surface faces the
// half-way direction of eye and light (the highlight). Scene units^2.
float specular_raw(Pt p) {
  // Sums over a window 3 cells wide centred on the point, each cell weighted
  // by its overlap: the sums vary continuously as the point moves over the
  // cells (a 3 x 3 block of whole cells would jump at every cell edge, and
  // the highlight's rim with it, as the camera moves).
  vec2 e = p.center / u_eye_cell - vec2(u_eye_min);
  float points = 0.0, covered = 0.0;
  ivec2 e0 = ivec2(floor(e - 1.5));
  for (int dy = 0; dy <= 3; ++dy)
    for (int dx = 0; dx <= 3; ++dx) {
      ivec2 c = e0 + ivec2(dx, dy);
      if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, u_eye_cells))) continue;
      float w = overlap(float(c.x), e.x - 1.5, e.x + 1.5) * overlap(float(c.y), e.y - 1.5, e.y + 1.5);
      uint i = uint(c.y) * uint(u_eye_cells.x) + uint(c.x);
      points += w * float(eye_count[i]);
      covered += w * float(eye_cover[i]);
    }
  float w = u_ortho != 0 ? 1.0 : p.depth;
  float px_area = w / u_px_per_unit;
  float eye_area = covered / (u_factor * u_factor) * px_area * px_area / max(points, 1.0);
  vec2 l = light_uv(p.view) * float(u_light_cells);
  float lpoints = 0.0, occupied = 0.0;
  ivec2 l0 = ivec2(floor(l - 1.5));
  for (int dy = 0; dy <= 3; ++dy)
    for (int dx = 0; dx <= 3; ++dx) {
      ivec2 c = l0 + ivec2(dx, dy);
      if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, ivec2(u_light_cells)))) continue;
      float w = overlap(float(c.x), l.x - 1.5, l.x + 1.5) * overlap(float(c.y), l.y - 1.5, l.y + 1.5);
      uint n = light_count[uint(c.y) * uint(u_light_cells) + uint(c.x)];
      lpoints += w * float(n);
      occupied += n > 0u ? w : 0.0;
    }
  float cell = u_light_extent / float(u_light_cells);
  float light_area = occupied * cell * cell / max(lpoints, 1.0);
  return eye_area + light_area;
}

// 8 bins per octave of 2^-64 .. 2^64: the octave from the exponent, the bin
// within it by the mantissa against 2^(k/8) (float bits, the constants of
// cpp/marks/stipples.h). Exact, unlike log2 (llvmpipe's approximates it):
// every device and the native passes bin alike.
const uint kBinEdges[7] = uint[7](0x3f8b95c2u, 0x3f9837f0u, 0x3fa5fed7u, 0x3fb504f3u, 0x3fc5672au, 0x3fd744fdu,
                                  0x3feac0c7u);
int specular_bin(float s) {
  uint b = floatBitsToUint(max(s, 1e-30));
  int octave = int(b >> 23) - 127;
  float mantissa = uintBitsToFloat((b & 0x007fffffu) | 0x3f800000u);
  int within = 0;
  for (int k = 0; k < 7; ++k) within += mantissa >= uintBitsToFloat(kBinEdges[k]) ? 1 : 0;
  return clamp((octave + 64) * 8 + within, 0, 1023);
}

void main() {
#if defined(PASS_DILATE) || defined(PASS_ERODE) || defined(PASS_COVER) || defined(PASS_REDUCE)
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
#if defined(PASS_REDUCE)
  int side = 1 << u_reduce_level;
  if (t.x >= side || t.y >= side) return;
  uint m = 0xffffffffu;
  for (int k = 0; k < 4; ++k) m = min(m, quad[quad_index(2 * t + ivec2(k & 1, k >> 1), u_reduce_level + 1)]);
  quad[quad_index(t, u_reduce_level)] = m;
#else
  if (any(greaterThanEqual(t, u_fine_size))) return;
#if defined(PASS_DILATE)
  // Each texel takes its neighbours' depths, each a step deeper.
  float d = uintBitsToFloat(hp[fine_index(t)]);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = t + ivec2(dx, dy);
      if ((dx == 0 && dy == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, u_fine_size))) continue;
      d = min(d, uintBitsToFloat(hp[fine_index(q)]) + u_offset);
    }
  hp_out[fine_index(t)] = floatBitsToUint(d);
#elif defined(PASS_ERODE)
  // Closing (the spreading, then as many erosions): the surface's area
  // without the fringe the spreading adds around its silhouette. Finite:
  // covered.
  bool all_in = true;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(t + ivec2(dx, dy), ivec2(0), u_fine_size - 1);
      all_in = all_in && !isinf(uintBitsToFloat(hp[fine_index(q)]));
    }
  hp_out[fine_index(t)] = all_in ? 0u : 0x7f800000u;
#else  // PASS_COVER: the surface area per eye cell
  if (!isinf(uintBitsToFloat(hp[fine_index(t)]))) {
    ivec2 c = eye_cell((vec2(t + u_fine_min) + 0.5) / u_factor);
    atomicAdd(eye_cover[uint(c.y) * uint(u_eye_cells.x) + uint(c.x)], 1u);
  }
#endif
#endif
#elif defined(PASS_RESOLVE)
  ivec2 q;
  if (!rect_pixel(q)) return;
  ivec2 t = clamp(ivec2(floor((vec2(q + u_origin) + 0.5) * u_factor)) - u_fine_min, ivec2(0), u_fine_size - 1);
  float surface = uintBitsToFloat(hp_out[fine_index(t)]);  // the spreading without the step
  bool on_surface = !isinf(surface) && u_paper.a > 0.0;
  uint pix = uint(q.y - u_clip_min.y) * uint(u_clip_max.x - u_clip_min.x) + uint(q.x - u_clip_min.x);
  float ink = uintBitsToFloat(dot_cov[pix]) * u_dot_color.a;
  float paper = on_surface ? u_paper.a : 0.0;
  float alpha = ink + paper * (1.0 - ink);
  if (alpha > 0.0) {
    vec3 rgb = (u_dot_color.rgb * ink + u_paper.rgb * paper * (1.0 - ink)) / alpha;
    float dot_d = uintBitsToFloat(dot_depth[pix]);
    float depth = ink > 0.0 ? min(dot_d, on_surface ? surface : INF) : surface;
    imageStore(u_color_out, q, vec4(clamp(rgb, 0.0, 1.0), alpha));
    imageStore(u_depth_out, q, vec4(depth));
  } else {
    imageStore(u_color_out, q, vec4(0.0));
    imageStore(u_depth_out, q, vec4(INF));
  }
#else
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  uint index = u_first + (u_queue != 0 ? queue_order[u_first + i] : i);
  Pt p = project(index);
#if defined(PASS_PROJECT)
  if (u_project_hp != 0 && p.inside) atomicMin(hp[fine_index(p.fine)], floatBitsToUint(p.depth));
  if (u_project_quad != 0 && u_diffuse != 0 && u_casters_all != 0 && p.depth >= u_near && p.depth <= u_far)
    atomicMin(quad[quad_index(light_texel(p.view, u_levels), u_levels)], light_key(p.view));
#elif defined(PASS_VISIBLE)
  if (!hp_visible(p)) return;
  bool frame = u_accumulate != 0 && owned(p);
  if (owned(p)) atomicAdd(visible_count, 1u);
  atomicMin(hp_out[fine_index(p.fine)], floatBitsToUint(p.depth));  // the visible surface, spread for the paper
  if (frame && u_diffuse != 0 && u_casters_all == 0)
    atomicMin(quad[quad_index(light_texel(p.view, u_levels), u_levels)], light_key(p.view));
  if (u_specular != 0) {
    ivec2 e = eye_cell(p.center);
    atomicAdd(eye_count[uint(e.y) * uint(u_eye_cells.x) + uint(e.x)], 1u);
    if (frame) {
      ivec2 l = light_cell(p.view);
      atomicAdd(light_count[uint(l.y) * uint(u_light_cells) + uint(l.x)], 1u);
    }
  }
#elif defined(PASS_SPECULAR)
  if (!hp_visible(p) || !owned(p)) return;
  // A histogram, not the maximum: a few outliers (cells cut by the
  // silhouette) would set a maximum; a percentile ignores them.
  atomicAdd(spec_hist[specular_bin(specular_raw(p))], 1u);
#elif defined(PASS_DRAW)
  if (!hp_visible(p)) return;
  uint id = point_ids[index];
  if (u_diffuse != 0) {
    // Fractional LEVEL: the finer level with probability frac.
    int level = u_level_lo + (hash01(id, 1u) < u_level_frac ? 1 : 0);
    ivec2 t = light_texel(p.view, u_levels) >> (u_levels - level);
    if (quad[quad_index(t, level)] == light_key(p.view)) return;  // the closest to the light in its cell
  }
  if (u_specular != 0 && u_tau > 0.0) {
    float diff = 1.0 - specular_raw(p) / u_spec_ref;
    if (diff < u_tau * hash01(id, 2u)) return;  // hidden with probability 1 - diff / tau
  }
  atomicAdd(kept_count, 1u);
  if (u_capture != 0) capture[atomicAdd(captured, 1u)].center_id = vec4(p.view, uintBitsToFloat(id));
  // 1 + jitter * (2h - 1), in the form NIR reassociates it to (the native
  // passes write the same, so both round alike).
  float diameter = max(u_dot_size * ((1.0 - u_size_jitter) + 2.0 * u_size_jitter * hash01(id, 3u)), 0.5);
  float r = 0.5 * diameter;
  ivec2 lo = max(ivec2(floor(p.center - r - 0.5)) - u_origin, u_clip_min);
  ivec2 hi = min(ivec2(ceil(p.center + r + 0.5)) - u_origin, u_clip_max - 1);
  uint depth_bits = floatBitsToUint(p.depth);
  int width = u_clip_max.x - u_clip_min.x;
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      // Area coverage of a disc (1 px wide antialiased edge, at least a
      // pixel's worth spread over the pixels a small dot touches).
      float dist = length(vec2(ivec2(x, y) + u_origin) + 0.5 - p.center);
      float cov = clamp(r + 0.5 - dist, 0.0, 1.0) * min(1.0, diameter * diameter);
      if (cov <= 0.0) continue;
      uint pix = uint(y - u_clip_min.y) * uint(width) + uint(x - u_clip_min.x);
      atomicMax(dot_cov[pix], floatBitsToUint(cov));
      atomicMin(dot_depth[pix], depth_bits);
    }
#endif
#endif
}
