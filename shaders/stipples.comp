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
#ifdef PASS_DRAW
// A compute stage gets 16 storage blocks (common drivers; llvmpipe counts
// every declared one): the dots pass, which never reads the visible
// surface, declares the splats' opacities (opacity_draws) in its place.
layout(std430, binding = 14) readonly buffer SplatOpacity { float splat_opacity[]; };
#else
layout(std430, binding = 4) buffer HiddenPointsOut { uint hp_out[]; };  // PASS_VISIBLE, PASS_RESOLVE: the visible surface
#endif
layout(std430, binding = 5) buffer Quadtree { uint quad[]; };        // levels 0..n in one 2^(n+1) x 2^n texture
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 7) buffer EyeCount { uint eye_count[]; };   // visible points per eye cell
layout(std430, binding = 8) buffer EyeCover { uint eye_cover[]; };   // covered fine texels per eye cell
layout(std430, binding = 9) buffer LightCount { uint light_count[]; };  // visible points per light cell
layout(std430, binding = 10) buffer DotCoverage { uint dot_cov[]; }; // per clip pixel, float bits (max)
layout(std430, binding = 11) buffer DotDepth { uint dot_depth[]; };  // per clip pixel, float bits (min)
// The counts and the specular histogram (log2 bins, 8 per octave) in one block: GL guarantees few.
layout(std430, binding = 12) buffer Globals {
  uint spec_total;
  uint visible_count;
  uint kept_count;
  uint captured;
  uint spec_hist[];
};
layout(std430, binding = 15) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices (u_queue)
uniform int u_queue;  // 1: invocation i takes the chunk's i-th point of the resolution queue
// level_scale spacing: the points' spacing (the colour attribute's binding: stipples read none)
// and the chunk's cell width over it (spacing_cell_scale). lit_rule share reads the normals
// (point_attributes.glsl's normals_u, binding 2, turned by packed_view_normal).
layout(std430, binding = 1) readonly buffer PointSpacing { float point_spacing[]; };
uniform float u_spacing_cell_scale;
uniform float u_spread_scale;  // spread_from_spacing: the chunk's spacing to spread_texels' scale,
uniform float u_spread_cap;    // and the largest spacing it spreads (the cloud's sparse spacing)
struct Captured { vec4 center_id; };  // view-space centre, point id (bits)
layout(std430, binding = 13) writeonly buffer Capture { Captured capture[]; };
#ifdef PASS_RESOLVE
layout(rgba32f, binding = 0) uniform writeonly image2D u_color_out;
layout(r32f, binding = 1) uniform writeonly image2D u_depth_out;
#endif

// Per pass: what a point pass does, and a step's depth (PASS_DILATE).
uniform int u_project_hp;      // PASS_PROJECT: into the fine texture
uniform int u_project_quad;    // PASS_PROJECT: every caster into the quadtree
uniform int u_accumulate;      // PASS_VISIBLE: the frame's counts of the owned points
uniform int u_reduce_level;    // PASS_REDUCE: the level written
uniform float u_step;          // PASS_DILATE: depth added per step
uniform float u_spec_ref;      // PASS_DRAW: the segment's high percentile of specular_raw
uniform int u_opacity_draws;   // PASS_DRAW: a dot only where id_rand(point id) < the splat's opacity
// points.glsl's kOpacitySalt (native.cpp: the same): the splats the points mark draws.
const uint kOpacitySalt = 0x6f706163u;

// What the shared kernels read of this pass's buffers.
uint hp_at(uint i) { return hp[i]; }
uint quad_at(uint i) { return quad[i]; }
uint eye_count_at(uint i) { return eye_count[i]; }
uint eye_cover_at(uint i) { return eye_cover[i]; }
uint light_count_at(uint i) { return light_count[i]; }
#include "shared_kernels.glsl"
#include "stipples_kernels.glsl"

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
  if (any(greaterThanEqual(t, win.fine_size))) return;
#if defined(PASS_DILATE)
  // Each texel takes its neighbours' depths, each a step deeper.
  float d = uintBitsToFloat(hp[fine_index(t)]);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = t + ivec2(dx, dy);
      if ((dx == 0 && dy == 0) || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, win.fine_size))) continue;
      d = min(d, uintBitsToFloat(hp[fine_index(q)]) + u_step);
    }
  hp_out[fine_index(t)] = floatBitsToUint(d);
#elif defined(PASS_ERODE)
  // Closing (the spreading, then as many erosions): the surface's area
  // without the fringe the spreading adds around its silhouette. Finite:
  // covered.
  bool all_in = true;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = clamp(t + ivec2(dx, dy), ivec2(0), win.fine_size - 1);
      all_in = all_in && !isinf(uintBitsToFloat(hp[fine_index(q)]));
    }
  hp_out[fine_index(t)] = all_in ? 0u : 0x7f800000u;
#else  // PASS_COVER: the surface area per eye cell
  if (!isinf(uintBitsToFloat(hp[fine_index(t)]))) {
    atomicAdd(eye_cover[eye_index((vec2(t + win.fine_min) + 0.5) / u.factor)], 1u);
  }
#endif
#endif
#elif defined(PASS_RESOLVE)
  ivec2 q;
  if (!rect_pixel(q)) return;
  ivec2 t = ivec2(resolve_texel(q.x + u_origin.x, 0), resolve_texel(q.y + u_origin.y, 1));
  uint pix = uint(q.y - u.clip_min.y) * uint(u.clip_max.x - u.clip_min.x) + uint(q.x - u.clip_min.x);
  StipplePixel out_px = resolve_pixel(uintBitsToFloat(dot_cov[pix]), uintBitsToFloat(dot_depth[pix]),
                                      uintBitsToFloat(hp_out[fine_index(t)]));  // the spreading without the step
  imageStore(u_color_out, q, out_px.color);
  imageStore(u_depth_out, q, vec4(out_px.depth));
#else
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  uint index = u_first + (u_queue != 0 ? queue_order[u_first + i] : i);
  Pt p = project(point_position(index), u_view_from_chunk);
#if defined(PASS_PROJECT)
  if (u_project_hp != 0 && p.inside) {
    // Its own spread (spread_from_spacing): a step deeper per texel, as the iterations' spreading.
    int r = u.spread_max > 0 ? spread_texels(p.depth, point_spacing[index], u_spread_cap, u_spread_scale) : 0;
    ivec2 lo = max(p.fine - r, ivec2(0)), hi = min(p.fine + r, win.fine_size - 1);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        ivec2 d = ivec2(x, y) - p.fine;
        if (!in_spread(d.x, d.y, r)) continue;
        atomicMin(hp[fine_index(ivec2(x, y))], floatBitsToUint(spread_depth(p, max(abs(d.x), abs(d.y)))));
      }
  }
  if (u_project_quad != 0 && u.quadtree != 0 && u.casters_all != 0 && p.in_depth)
    atomicMin(quad[quad_index(light_texel(p.view, u.levels), u.levels)], light_key(p.view));
#elif defined(PASS_VISIBLE)
  if (!hp_visible(p)) return;
  bool frame = u_accumulate != 0 && owned(p);
  if (owned(p)) atomicAdd(visible_count, 1u);
  // The visible surface, spread for the paper (its own spread included, without the step).
  int r = u.spread_max > 0 ? spread_texels(p.depth, point_spacing[index], u_spread_cap, u_spread_scale) : 0;
  ivec2 lo = max(p.fine - r, ivec2(0)), hi = min(p.fine + r, win.fine_size - 1);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      if (in_spread(x - p.fine.x, y - p.fine.y, r)) atomicMin(hp_out[fine_index(ivec2(x, y))], floatBitsToUint(p.depth));
  if (frame && u.quadtree != 0 && u.casters_all == 0)
    atomicMin(quad[quad_index(light_texel(p.view, u.levels), u.levels)], light_key(p.view));
  if (u.specular != 0 || u.tone_scale > 0.0) atomicAdd(eye_count[eye_index(p.center)], 1u);
  if (u.specular != 0 && frame) atomicAdd(light_count[light_cell_index(p.view)], 1u);
#elif defined(PASS_SPECULAR)
  if (!hp_visible(p) || !owned(p)) return;
  // A histogram, not the maximum: a few outliers (cells cut by the
  // silhouette) would set a maximum; a percentile ignores them.
  float cell_target = u.level_from_spacing != 0 ? point_spacing[index] * u_spacing_cell_scale : 0.0;
  atomicAdd(spec_hist[specular_bin(specular_measure(p, cell_target))], 1u);
#elif defined(PASS_DRAW)
  if (!hp_visible(p)) return;
  uint id = point_ids[index];
  if (u_opacity_draws != 0 && !(id_rand(id, kOpacitySalt, 0u) < splat_opacity[index])) return;
  float cell_target = u.level_from_spacing != 0 ? point_spacing[index] * u_spacing_cell_scale : 0.0;
  vec3 n = u.lit_share != 0 ? packed_view_normal(normals_u[index], u_view_from_chunk) : vec3(0.0);
  float lit = u.diffuse != 0 ? lit_scale(p, id, cell_target, n) : 1.0;
  if (lit <= 0.0) return;
  if (u.specular != 0 && u.tau > 0.0 && specular_out(id, specular_measure(p, cell_target), u_spec_ref)) return;
  Dot dot = tone_dot(p, id);
  dot.diameter *= lit;
  if (dot.diameter <= 0.0) return;
  float diameter = dot.diameter;
  atomicAdd(kept_count, 1u);
  if (u.capture != 0) capture[atomicAdd(captured, 1u)].center_id = vec4(p.view, uintBitsToFloat(id));
  float r = 0.5 * diameter;
  ivec2 lo = max(ivec2(floor(dot.center - r - 0.5)) - u.origin_px, u.clip_min);
  ivec2 hi = min(ivec2(ceil(dot.center + r + 0.5)) - u.origin_px, u.clip_max - 1);
  uint depth_bits = floatBitsToUint(p.depth);
  int width = u.clip_max.x - u.clip_min.x;
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      vec2 d = vec2(ivec2(x, y) + u.origin_px) + 0.5 - dot.center;
      float cov = dot_coverage(d.x, d.y, diameter);
      if (cov <= 0.0) continue;
      uint pix = uint(y - u.clip_min.y) * uint(width) + uint(x - u.clip_min.x);
      atomicMax(dot_cov[pix], floatBitsToUint(cov));
      atomicMin(dot_depth[pix], depth_bits);
    }
#endif
#endif
}
