// The gap fill's second stage (cpp/render/filter_chain.cpp, after the line
// search of gap_fill.comp): gaps among lone splats, which no line through
// the gap meets on both sides (a field of small dots on a sparse canopy, a
// range scan's lattice seen obliquely). The surface's pixels are pooled into
// cells of 2 to 2^GAP_LEVELS px (16; PASS_PULL, a level from the one below; each cell
// keeps only its nearest surface: children farther than that surface's
// steepest slope over the cell lie behind it). A pixel is enclosed at a
// level when a square of 2x2 cells about its own holds the surface, their
// centroids lie
// around it (it is inside their convex hull: a silhouette never grows, a
// thin object in front keeps its edges), no two of them farther apart than
// twice the scan's spacing there (a gap between neighbouring samples, not a
// hole in the scan nor an opening in foliage), and their depths one surface
// (within its steepest slope over their distance). The finest such square
// fills the pixel with the cells' inverse-distance mean (PASS_PUSH): a
// background pixel, or a covered one lying behind that surface by more than
// its slope and twice the cells' depth spread (the scan's noise): a back
// point seen through the front surface's gaps.
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
layout(rg32f, binding = 5) uniform image2D u_front;     // per cell: nearest depth, largest spacing
uniform int u_pixel_spacing;  // 1: u_spacing holds the points' spacing
uniform float u_span;         // twice the segment's spacing, view units (0: unknown)
uniform float u_grazing;      // tan of the steepest surface angle (kSteepestSurfaceSlope)
uniform int u_level_x[GAP_LEVELS];  // each level's first atlas column
// Each level's pooled cells (frame cells, max exclusive): others are empty
// (the atlas holds earlier frames' there).
uniform ivec2 u_cells_min[GAP_LEVELS], u_cells_max[GAP_LEVELS];
uniform ivec2 u_write_min, u_write_max;  // the pixels the fill wrote: the only ones pooled or changed
uniform ivec2 u_cover_min, u_cover_max;  // covered pixels lie within

float pixel_size(float d) { return abs(u_surface_x0.x + d * u_surface_x1.x); }

ivec2 floor_div(ivec2 a, int s) { return ivec2(floor(vec2(a) / float(s))); }
// Atlas texel of frame cell c at level L (1..GAP_LEVELS).
ivec2 slot(int level, ivec2 c) {
  return ivec2(u_level_x[level - 1], 0) + c - floor_div(u_origin, 1 << level) + 1;
}

struct Cell {
  vec4 sum;
  float n, depth_sum, front, spacing;
  vec2 xy_sum;
};

Cell empty_cell() { return Cell(vec4(0.0), 0.0, 0.0, INF, 0.0, vec2(0.0)); }

// Frame cell c of `level`; level 0 is the pixel (local c - u_origin).
Cell read_cell(int level, ivec2 c) {
  if (level == 0) {
    ivec2 p = c - u_origin;
    Cell cell = empty_cell();
    if (any(lessThan(p, max(u_write_min, u_cover_min))) || any(greaterThanEqual(p, min(u_write_max, u_cover_max))))
      return cell;
    vec4 color = imageLoad(u_image, p);
    float d = imageLoad(u_depth, p).r;
    if (!covered(color) || isinf(d)) return cell;  // background, or a filter's paint with no surface
    return Cell(color, 1.0, d, d, u_pixel_spacing != 0 ? imageLoad(u_spacing, p).r : 0.0, vec2(c) + 0.5);
  }
  if (any(lessThan(c, u_cells_min[level - 1])) || any(greaterThanEqual(c, u_cells_max[level - 1]))) return empty_cell();
  ivec2 q = slot(level, c);
  vec4 stats = imageLoad(u_stats, q);
  if (stats.x == 0.0) return empty_cell();
  vec2 front = imageLoad(u_front, q).rg;
  return Cell(imageLoad(u_sum, q), stats.x, stats.y, front.x, front.y, stats.zw);
}

#ifdef PASS_PULL
uniform int u_level;  // the level written, 1..GAP_LEVELS; u_rect_min/max: its frame cells
layout(local_size_x = 16, local_size_y = 16) in;
void main() {
  ivec2 c = u_rect_min + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(c, u_rect_max))) return;
  Cell child[4];
  float near = INF;
  for (int k = 0; k < 4; ++k) {
    child[k] = read_cell(u_level - 1, 2 * c + ivec2(k & 1, k >> 1));
    near = min(near, child[k].front);
  }
  // Children whose nearest point lies behind the nearest surface by more
  // than its slope over the cell (its side) are another surface seen
  // through it.
  float limit = near + float(1 << u_level) * pixel_size(near) * u_grazing;
  Cell cell = empty_cell();
  for (int k = 0; k < 4; ++k) {
    if (child[k].n == 0.0 || child[k].front > limit) continue;
    cell.sum += child[k].sum;
    cell.n += child[k].n;
    cell.depth_sum += child[k].depth_sum;
    cell.xy_sum += child[k].xy_sum;
    cell.front = min(cell.front, child[k].front);
    cell.spacing = max(cell.spacing, child[k].spacing);
  }
  ivec2 q = slot(u_level, c);
  imageStore(u_sum, q, cell.sum);
  imageStore(u_stats, q, vec4(cell.n, cell.depth_sum, cell.xy_sum));
  imageStore(u_front, q, vec4(cell.front, cell.spacing, 0.0, 0.0));
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

layout(local_size_x = 16, local_size_y = 16) in;
void main() {
  ivec2 p;
  if (!rect_pixel(p) || any(lessThan(p, u_cover_min)) || any(greaterThanEqual(p, u_cover_max))) return;
  vec4 color = imageLoad(u_image, p);
  float own = covered(color) ? imageLoad(u_depth, p).r : INF;
  if (covered(color) && isinf(own)) return;  // a filter's paint: kept
  ivec2 frame_p = p + u_origin;
  // A covered pixel with no point nearer than it among the coarsest 3x3
  // cells (which hold every finer cell read below) is kept.
  if (!isinf(own)) {
    ivec2 c = floor_div(frame_p, 1 << GAP_LEVELS);
    float near = INF;
    for (int k = 0; k < 9; ++k) near = min(near, read_cell(GAP_LEVELS, c + ivec2(k % 3 - 1, k / 3 - 1)).front);
    if (own <= near) return;
  }
  vec2 x = vec2(frame_p) + 0.5;
  for (int level = 1; level <= GAP_LEVELS; ++level) {
    // The 3x3 cells around the pixel's own, row by row, and the 4 squares
    // of 2x2 cells among them that hold it: a cell's centroid need not lie
    // at its centre, so the pixel may lie among any 4 that meet at its cell.
    float side = float(1 << level);
    ivec2 own_cell = floor_div(frame_p, 1 << level);
    Cell cells[9];
    for (int k = 0; k < 9; ++k) cells[k] = read_cell(level, own_cell + ivec2(k % 3 - 1, k / 3 - 1));
    // The square whose cell centres bracket the pixel first: its bilinear
    // weights run on continuously into the next pixel's (no step in the
    // filled depth for eye-dome lighting to draw).
    ivec2 bracket = ivec2(floor(x / side - 0.5)) - (own_cell - 1);  // 0 or 1 each
    int standard = bracket.x + 2 * bracket.y;
    for (int n = 0; n < 4; ++n) {
      int square = n ^ standard;
      ivec2 corner = ivec2(square & 1, square >> 1);
      int first = corner.x + 3 * corner.y;
      // Around the square in turn: (0,0), (1,0), (1,1), (0,1).
      int index[4] = int[4](first, first + 1, first + 4, first + 3);
      Cell cell[4];
      vec2 centre[4];
      float lo = INF, hi = 0.0, spacing = 0.0;
      bool all_met = true;
      for (int k = 0; k < 4; ++k) {
        cell[k] = cells[index[k]];
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
      float span = max(u_span, 2.0 * spacing);  // the longest gap between the scan's neighbours
      if (!(size > 0.0) || longest * size > span || hi - lo > longest * size * u_grazing) continue;
      // A covered pixel gives way only to a surface it cannot belong to
      // (nearer than it by more than that surface's slope over the square,
      // and than twice the square's depth spread: the scan's noise); its
      // own surface's squares are looked past, the finer ones may hold only
      // the points behind. A background pixel: the first square decides.
      if (!isinf(own) && (own <= hi + longest * size * u_grazing || own - hi <= 2.0 * (hi - lo) + size * u_grazing))
        continue;
      // Bilinear between the cells' means by the pixel's place among their
      // centres (clamped to the square's edge when it lies outside them).
      vec2 f = clamp(x / side - 0.5 - vec2(own_cell - 1 + corner), 0.0, 1.0);
      vec4 w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), f.x * f.y, (1.0 - f.x) * f.y);
      vec4 sum = vec4(0.0);
      float depth = 0.0;
      for (int k = 0; k < 4; ++k) {
        sum += w[k] * cell[k].sum / cell[k].n;
        depth += w[k] * cell[k].depth_sum / cell[k].n;
      }
      imageStore(u_image, p, sum);
      imageStore(u_depth, p, vec4(depth));
      return;
    }
  }
}
#endif
