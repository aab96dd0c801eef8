// The gap fill's second stage (cpp/render/filter_chain.cpp, after the line
// search of gap_fill.comp): gaps among lone splats, which no line through
// the gap meets on both sides (small dots scattered over a sparse canopy or
// river; the ground seen through a roof's scan lines).
//
// PASS_PULL pools the line-filled pixels into cells of 2 to 2^GAP_LEVELS px
// (16), a level from the one below. A cell keeps only its nearest surface:
// children whose nearest point lies behind it by more than its steepest
// slope over a cell side are another surface seen through it.
//
// A pixel is enclosed at a level by a square of 2x2 cells among the 3x3
// about its own when the four hold the surface, the pixel lies in the
// convex hull of their centroids (a silhouette never grows, a thin object
// in front keeps its edges), their side and their centroids' distances are
// within twice the scan's spacing there (a gap between neighbouring
// samples, not a hole in the scan nor an opening in foliage), and their
// depths are one surface (within its steepest slope over their distance).
// The finest such square fills a background pixel bilinearly between its
// cells' means; a covered pixel gives way to one nearer than it by more
// than its slope over the square and twice its depth spread (a back point
// seen through the front surface's gaps).
//
// PASS_NEAR sums up per cell what its squares allow, PASS_LIST lists the
// pixels that may change, and the push (no pass define) runs on the list.
// GAP_LEVELS is kGapLevels (cpp/render/filter_chain.h).
// variants: PASS_PULL PULL_PIXELS GAP_LEVELS=4 | PASS_PULL GAP_LEVELS=4 | PASS_NEAR GAP_LEVELS=4 | PASS_LIST GAP_LEVELS=4 | GAP_LEVELS=4
//
// Cells sit on the frame's grid (pixel + u_origin), so a tile of the frame
// pools the same cells; the push reads pixels at most 2 coarsest cells
// away (kGapPushReach). Cell c of level L (side 2^L) is stored at
// u_level_x[L - 1] + c - floor(u_origin / 2^L) + 1 of an atlas row per
// level: one column and row to spare on either side.
#include "filter_common.glsl"
layout(rgba32f, binding = 0) uniform image2D u_image;   // the fill's colours (straight rgba)
layout(r32f, binding = 1) uniform image2D u_depth;      // the fill's depths (+inf: no point)
layout(r32f, binding = 2) uniform readonly image2D u_spacing;  // each point's spacing, view units (0: unknown)
layout(rgba32f, binding = 3) uniform image2D u_sum;     // per cell: colour sum
layout(rgba32f, binding = 4) uniform image2D u_stats;   // per cell: count, depth sum, centroid x and y sums (frame px)
// Per cell: nearest depth, largest spacing; then PASS_NEAR's summary of
// the squares of cells about it.
layout(rgba32f, binding = 5) uniform image2D u_front;
uniform int u_pixel_spacing;  // 1: u_spacing holds the points' spacing
uniform float u_span;         // twice the segment's spacing, view units (0: unknown)
uniform float u_grazing;      // tan of the steepest surface angle (kSteepestSurfaceSlope)
uniform int u_level_x[GAP_LEVELS];  // each level's first atlas column
// Each level's pooled cells (frame cells, max exclusive): others are empty
// (the atlas holds earlier frames' there).
uniform ivec2 u_cells_min[GAP_LEVELS], u_cells_max[GAP_LEVELS];
uniform ivec2 u_write_min, u_write_max;  // the pixels the fill wrote: the only ones pooled or changed
uniform ivec2 u_cover_min, u_cover_max;  // covered pixels lie within

ivec2 floor_div(ivec2 a, int s) { return ivec2(floor(vec2(a) / float(s))); }
// Atlas texel of frame cell c at level L (1..GAP_LEVELS).
ivec2 slot(int level, ivec2 c) {
  return ivec2(u_level_x[level - 1], 0) + c - floor_div(u_origin, 1 << level) + 1;
}

// A cell's colour sum is read apart (u_sum), where it is used.
struct Cell {
  float n, depth_sum, front, spacing;
  vec2 xy_sum;
};

Cell empty_cell() { return Cell(0.0, 0.0, INF, 0.0, vec2(0.0)); }

// Frame pixel c as a cell of level 0, and its colour.
Cell read_pixel(ivec2 c, out vec4 color) {
  ivec2 p = c - u_origin;
  color = vec4(0.0);
  if (any(lessThan(p, max(u_write_min, u_cover_min))) || any(greaterThanEqual(p, min(u_write_max, u_cover_max))))
    return empty_cell();
  color = imageLoad(u_image, p);
  float d = imageLoad(u_depth, p).r;
  if (!covered(color) || isinf(d)) return empty_cell();  // background, or a filter's paint with no surface
  return Cell(1.0, d, d, u_pixel_spacing != 0 ? imageLoad(u_spacing, p).r : 0.0, vec2(c) + 0.5);
}

// Frame cell c of `level` (1..GAP_LEVELS).
Cell read_cell(int level, ivec2 c) {
  if (any(lessThan(c, u_cells_min[level - 1])) || any(greaterThanEqual(c, u_cells_max[level - 1]))) return empty_cell();
  ivec2 q = slot(level, c);
  vec4 stats = imageLoad(u_stats, q);
  if (stats.x == 0.0) return empty_cell();
  vec2 front = imageLoad(u_front, q).rg;
  return Cell(stats.x, stats.y, front.x, front.y, stats.zw);
}
// The colour sum of a cell read_cell found holding points.
vec4 cell_sum(int level, ivec2 c) { return imageLoad(u_sum, slot(level, c)); }

#ifdef PASS_PULL
// The level written, 1..GAP_LEVELS (PULL_PIXELS: 1, from the pixels);
// u_rect_min/max: its frame cells.
uniform int u_level;
layout(local_size_x = 16, local_size_y = 16) in;
void main() {
  ivec2 c = u_rect_min + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, u_rect_max))) return;
  Cell child[4];
  vec4 color[4];  // the pixels' colours (level 1), read once
  float near = INF;
  for (int k = 0; k < 4; ++k) {
    ivec2 q = 2 * c + ivec2(k & 1, k >> 1);
#ifdef PULL_PIXELS
    child[k] = read_pixel(q, color[k]);
#else
    child[k] = read_cell(u_level - 1, q);
#endif
    near = min(near, child[k].front);
  }
  // Children whose nearest point lies behind the nearest surface by more
  // than its slope over the cell (its side) are another surface seen
  // through it.
  float limit = near + float(1 << u_level) * pixel_size(near) * u_grazing;
  Cell cell = empty_cell();
  vec4 sum = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    if (child[k].n == 0.0 || child[k].front > limit) continue;
#ifdef PULL_PIXELS
    sum += color[k];
#else
    sum += cell_sum(u_level - 1, 2 * c + ivec2(k & 1, k >> 1));
#endif
    cell.n += child[k].n;
    cell.depth_sum += child[k].depth_sum;
    cell.xy_sum += child[k].xy_sum;
    cell.front = min(cell.front, child[k].front);
    cell.spacing = max(cell.spacing, child[k].spacing);
  }
  ivec2 q = slot(u_level, c);
  imageStore(u_sum, q, sum);
  imageStore(u_stats, q, vec4(cell.n, cell.depth_sum, cell.xy_sum));
  imageStore(u_front, q, vec4(cell.front, cell.spacing, 0.0, 0.0));
}
#elif defined(PASS_NEAR)
// Per cell of level u_level (u_rect_min/max), what the push asks first of
// the 4 squares of 2x2 cells about it that hold it, beside the cell's own
// nearest depth and spacing (which its neighbours read, and which stay):
// whether one holds the surface where the scan's spacing asks for cells
// this large (their side within that gap at their nearest depth: a pixel
// spans no less farther away), and the least depth a covered pixel must
// lie behind to give way to one (its deepest cell's mean depth and the
// steepest slope over a cell).
uniform int u_level;
layout(local_size_x = 16, local_size_y = 16) in;
// The group's cells and one around them, each read once: per cell its
// nearest and mean depth (+inf: empty) and the longest gap between the
// scan's neighbours there, view units.
shared vec3 s_cells[18 * 18];
void main() {
  ivec2 group_min = u_rect_min + ivec2(gl_WorkGroupID.xy) * 16 - 1;
  for (uint i = gl_LocalInvocationIndex; i < 18u * 18u; i += 256u) {
    Cell cell = read_cell(u_level, group_min + ivec2(int(i % 18u), int(i / 18u)));
    s_cells[i] = vec3(cell.front, cell.n > 0.0 ? cell.depth_sum / cell.n : INF, max(u_span, 2.0 * cell.spacing));
  }
  barrier();
  ivec2 c = u_rect_min + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, u_rect_max))) return;
  float side = float(1 << u_level);
  vec3 met[9];  // the 3x3 cells about this one, row by row
  ivec2 l = ivec2(gl_LocalInvocationID.xy);
  for (int k = 0; k < 9; ++k) met[k] = s_cells[(l.y + k / 3) * 18 + l.x + k % 3];
  float square_met = 0.0, behind = INF;
  for (int square = 0; square < 4; ++square) {
    int first = (square & 1) + 3 * (square >> 1);
    vec3 a = met[first], b = met[first + 1], d = met[first + 3], e = met[first + 4];
    if (isinf(max(max(a.x, b.x), max(d.x, e.x)))) continue;  // a cell without points
    float front = min(min(a.x, b.x), min(d.x, e.x));
    float lo = min(min(a.y, b.y), min(d.y, e.y)), hi = max(max(a.y, b.y), max(d.y, e.y));
    if (max(max(a.z, b.z), max(d.z, e.z)) >= side * pixel_size(front)) square_met = 1.0;
    behind = min(behind, hi + side * pixel_size(lo) * u_grazing);
  }
  ivec2 q = slot(u_level, c);
  imageStore(u_front, q, vec4(imageLoad(u_front, q).rg, behind, square_met));
}
#else
// The pixels the push may change, listed (PASS_LIST) and searched (the
// push, dispatched indirectly from the list's count, 64 to a group):
// llvmpipe runs the search's loads for every lane of a group where any
// lane needs them, so only listed pixels share groups.
layout(std430, binding = 3) buffer Work {
  uint groups_x, groups_y, groups_z, count;
  uint pixels[];  // x | y << 16
};

// Whether a pixel at depth `own` (+inf: background) in `cell` of `level`
// may change there (PASS_NEAR's summary of the squares about that cell).
bool level_may_change(int level, ivec2 cell, float own) {
  vec2 around = imageLoad(u_front, slot(level, cell)).ba;
  return isinf(own) ? around.y > 0.0 : own > around.x;
}

// Whether pixel p may change: a background pixel whose cell at some level
// lies in a square of cells holding the surface, or a covered one behind
// such a square by more than the push's rule (below) asks at least
// (PASS_NEAR). Paint without depth is kept.
bool may_change(ivec2 p) {
  if (any(lessThan(p, u_cover_min)) || any(greaterThanEqual(p, u_cover_max))) return false;
  vec4 color = imageLoad(u_image, p);
  float own = covered(color) ? imageLoad(u_depth, p).r : INF;
  if (covered(color) && isinf(own)) return false;
  ivec2 frame_p = p + u_origin;
  for (int level = 1; level <= GAP_LEVELS; ++level)
    if (level_may_change(level, floor_div(frame_p, 1 << level), own)) return true;
  return false;
}

#ifdef PASS_LIST
layout(local_size_x = 16, local_size_y = 16) in;
shared uint s_count, s_base;
void main() {
  if (gl_LocalInvocationIndex == 0u) s_count = 0u;
  barrier();
  ivec2 p;
  bool work = rect_pixel(p) && may_change(p);
  uint slot_in_group = work ? atomicAdd(s_count, 1u) : 0u;
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    s_base = atomicAdd(count, s_count);
    atomicMax(groups_x, min((s_base + s_count + 63u) / 64u, 65535u));  // the push strides over a longer list
  }
  barrier();
  if (work) pixels[s_base + slot_in_group] = uint(p.x) | (uint(p.y) << 16);
}
#else
// Whether x lies in triangle (a, b, c), edges included.
bool in_triangle(vec2 x, vec2 a, vec2 b, vec2 c) {
  float d0 = (b.x - a.x) * (x.y - a.y) - (b.y - a.y) * (x.x - a.x);
  float d1 = (c.x - b.x) * (x.y - b.y) - (c.y - b.y) * (x.x - b.x);
  float d2 = (a.x - c.x) * (x.y - c.y) - (a.y - c.y) * (x.x - c.x);
  return !((d0 < 0.0 || d1 < 0.0 || d2 < 0.0) && (d0 > 0.0 || d1 > 0.0 || d2 > 0.0));
}
// Whether x lies in the convex hull of the 4 points: in one of the 4
// triangles of 3 of them.
bool in_hull(vec2 x, vec2 c[4]) {
  return in_triangle(x, c[0], c[1], c[2]) || in_triangle(x, c[0], c[2], c[3]) || in_triangle(x, c[0], c[1], c[3]) ||
         in_triangle(x, c[1], c[2], c[3]);
}

void push(ivec2 p) {
  vec4 color = imageLoad(u_image, p);
  float own = covered(color) ? imageLoad(u_depth, p).r : INF;
  ivec2 frame_p = p + u_origin;
  vec2 x = vec2(frame_p) + 0.5;
  for (int level = 1; level <= GAP_LEVELS; ++level) {
    // The 4 squares of 2x2 cells among the 3x3 about the pixel's own that
    // hold it: a cell's centroid need not lie at its centre, so the pixel
    // may lie among any 4 that meet at its cell. Cells are read as a
    // square needs them (llvmpipe pays every load for the whole group).
    float side = float(1 << level);
    ivec2 own_cell = floor_div(frame_p, 1 << level);
    if (!level_may_change(level, own_cell, own)) continue;
    // The square whose cell centres bracket the pixel first: its bilinear
    // weights run on continuously into the next pixel's (no step in the
    // filled depth for eye-dome lighting to draw).
    ivec2 bracket = ivec2(floor(x / side - 0.5)) - (own_cell - 1);  // 0 or 1 each
    int standard = bracket.x + 2 * bracket.y;
    for (int n = 0; n < 4; ++n) {
      int square = n ^ standard;
      ivec2 corner = own_cell - 1 + ivec2(square & 1, square >> 1);
      Cell cell[4];
      vec2 centre[4];
      float lo = INF, hi = 0.0, spacing = 0.0;
      bool all_met = true;
      for (int k = 0; k < 4; ++k) {
        // Around the square in turn: (0,0), (1,0), (1,1), (0,1).
        cell[k] = read_cell(level, corner + ivec2(k == 1 || k == 2 ? 1 : 0, k >= 2 ? 1 : 0));
        all_met = all_met && cell[k].n > 0.0;
        centre[k] = cell[k].xy_sum / max(cell[k].n, 1.0);
        float d = cell[k].depth_sum / max(cell[k].n, 1.0);
        lo = min(lo, d);
        hi = max(hi, d);
        spacing = max(spacing, cell[k].spacing);
      }
      if (!all_met || !in_hull(x, centre)) continue;
      float longest = 0.0;  // px
      for (int k = 0; k < 4; ++k) longest = max(longest, distance(centre[k], centre[(k + 1) & 3]));
      float size = pixel_size(lo);
      // The longest gap between the scan's neighbours: the cells' side and
      // their centroids' distance within it (cells wider than the scan's
      // gaps there would close holes in it).
      float span = max(u_span, 2.0 * spacing);
      if (!(size > 0.0) || max(longest, side) * size > span || hi - lo > longest * size * u_grazing) continue;
      // A covered pixel gives way only to a surface it cannot belong to
      // (nearer than it by more than that surface's slope over the square,
      // at least a cell, and than twice the square's depth spread: the
      // scan's noise); its own surface's squares are looked past, the finer
      // ones may hold only the points behind. A background pixel: the first
      // square decides.
      if (!isinf(own) && (own <= hi + max(longest, side) * size * u_grazing ||
                          own - hi <= 2.0 * (hi - lo) + size * u_grazing))
        continue;
      // Bilinear between the cells' means by the pixel's place among their
      // centres (clamped to the square's edge when it lies outside them).
      vec2 f = clamp(x / side - 0.5 - vec2(corner), 0.0, 1.0);
      vec4 w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), f.x * f.y, (1.0 - f.x) * f.y);
      vec4 sum = vec4(0.0);
      float depth = 0.0;
      for (int k = 0; k < 4; ++k) {
        sum += w[k] * cell_sum(level, corner + ivec2(k == 1 || k == 2 ? 1 : 0, k >= 2 ? 1 : 0)) / cell[k].n;
        depth += w[k] * cell[k].depth_sum / cell[k].n;
      }
      imageStore(u_image, p, sum);
      imageStore(u_depth, p, vec4(depth));
      return;
    }
  }
}

layout(local_size_x = 64) in;
void main() {
  for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * 64u)
    push(ivec2(pixels[i] & 0xffffu, pixels[i] >> 16));
}
#endif
#endif
