// Depth-aware gap fill before the filters that read neighbourhoods
// (cpp/render/filter_chain.cpp). A pixel is a gap of a surface when that
// surface's own pixels enclose it: along at least 2 of the 4 lines through
// it (horizontal, vertical, both diagonals) the first pixel of the surface
// lies within the pixel's reach on both sides (g_reach, below), and the two ends are one surface: their
// depths differ by no more than a surface seen at the steepest angle
// (u_grazing = tan of it) can change over the gap, the gap's length times
// the pixel's footprint at that depth, and the gap is one between the
// scan's neighbouring samples: no longer than twice the scan's spacing (the
// diameter of a neighbourhood; u_span, 0 where unknown) at the ends' depth,
// so splats narrower than the scan-line gaps of an aerial tile still close
// them while a hole in the scan stays, or, within u_splat_reach, on either
// side the surface runs on for at least half the gap (its splats are as
// wide as its gaps, where the scan is sparser than its spacing: lone
// splats do not merge, nor join a surface). Covered pixels count as gaps
// too when a surface nearer than them by more than its slope over the whole
// search, and more than twice the depth spread of its own enclosing pixels
// (the scan's local noise), encloses them: back points seen through a front
// surface. A gap takes the inverse-distance mean of its enclosing pixels
// (rgba, straight alpha). The nearer surface never crosses a depth jump:
// the background beside a silhouette stays, but where a background pixel's
// lines meet a nearer surface on one side and a farther one on the other
// (a jump, or a gap between the farther surface's own samples), that
// surface, which runs on behind the nearer one's edge, fills it (a tree
// crown's gaps, a wall in a depth camera's shadow beside an occluder). Passes: line sweeps, classify, the search on the listed
// pixels, then twice the pinholes (PASS_SPECK; see the end of the file).
#include "filter_common.glsl"
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(r32f, binding = 2) uniform readonly image2D u_depth;
layout(r32f, binding = 7) uniform writeonly image2D u_depth_out;  // the fill pass's
uniform int u_reach;        // the farthest search (px)
uniform int u_reach_floor;  // the nearest reach every pixel searches (the segment's spacing), px
uniform float u_grazing;
uniform float u_span;  // the longest gap between the scan's neighbours, view units (0: unknown)
uniform int u_splat_reach;  // the reach of the splat-width rule (below), px
// Each covered pixel's point's own spacing, view units (0: unknown), read
// where u_pixel_spacing is 1: where the scan is sparser than the segment's
// spacing (an aerial tile's water, a far bank) its own gaps close too.
layout(r32f, binding = 6) uniform readonly image2D u_spacing;
uniform int u_pixel_spacing;
// The longest gap between the scan's neighbours at covered pixel q.
float span_at(ivec2 q) { return u_pixel_spacing != 0 ? max(u_span, 2.0 * imageLoad(u_spacing, q).r) : u_span; }
uniform ivec2 u_cover_min;  // covered pixels lie within [u_cover_min, u_cover_max)
uniform ivec2 u_cover_max;

struct Hit {
  int t;  // 0: none within reach
  float depth;
  vec4 color;
};

// How far this pixel's search goes: the segment's reach (u_reach_floor),
// or further, up to u_reach, where the points it meets are sparser (set by
// fill_pixel from its own hits, so a tile of the frame finds the same).
int g_reach = 0;

// The first pixel along `dir` nearer than `behind` (covered, finite depth).
// How many steps along `dir` stay within the covered box, up to g_reach.
int steps_inside(ivec2 p, ivec2 dir) {
  ivec2 room = mix(mix(ivec2(g_reach), p - u_cover_min, lessThan(dir, ivec2(0))), u_cover_max - 1 - p,
                   greaterThan(dir, ivec2(0)));
  return min(g_reach, min(room.x, room.y));
}

// The search's first covered pixels from a background pixel (march with
// `behind` +inf: any covered pixel with a depth stops it) are read from the
// sweeps (PASS_SWEEP, below): one load per direction whatever the reach.
// u_runs holds, per pixel, its line's distances ahead (.r) and behind (.g)
// to the nearest such pixel (0: none within 16), a layer per orientation:
// horizontal, vertical, diagonal (1, 1), antidiagonal (1, -1).
layout(rg8ui, binding = 5) uniform uimage2DArray u_runs;
int orientation(ivec2 dir) { return dir.y == 0 ? 0 : dir.x == 0 ? 1 : dir.x == dir.y ? 2 : 3; }

Hit march(ivec2 p, ivec2 dir, float behind) {
  int n = steps_inside(p, dir);
  if (isinf(behind)) {
    int o = orientation(dir);
    uvec4 run = imageLoad(u_runs, ivec3(p, o));
    // Ahead along the orientation's own direction (x increasing; y for columns).
    int t = int((o == 1 ? dir.y : dir.x) > 0 ? run.r : run.g);
    if (t == 0 || t > n) return Hit(0, INF, vec4(0.0));
    ivec2 q = p + t * dir;
    return Hit(t, imageLoad(u_depth, q).r, imageLoad(u_in, q));
  }
  // Depths only in the loop, the colour once after it (llvmpipe runs a
  // load in a loop for every lane while any lane needs it).
  for (int k = 1; k <= n; ++k) {
    float d = INF;
    for (; k <= n; ++k) {
      d = imageLoad(u_depth, p + k * dir).r;  // +inf where no point is
      if (d < behind) break;
    }
    if (k > n) break;
    vec4 c = imageLoad(u_in, p + k * dir);
    if (covered(c)) return Hit(k, d, c);
  }
  return Hit(0, INF, vec4(0.0));
}

// How many pixels with points nearer than `limit` (the surface, not what
// lies behind it) follow the hit at `t` along `dir`, up to `cap`.
int run_length(ivec2 p, ivec2 dir, int t, float limit, int cap) {
  int n = 0, last = min(t + cap, steps_inside(p, dir));
  for (int k = t + 1; k <= last; ++k) {
    if (!(imageLoad(u_depth, p + k * dir).r <= limit)) break;  // +inf: no point
    ++n;
  }
  return n;
}

// The 8 directions in turn around a pixel, 0 to 7: (1,0), (1,1), (0,1),
// (-1,1), (-1,0), (-1,-1), (0,-1), (1,-1); direction k + 4 is k's opposite.
const ivec2 AROUND[8] = ivec2[8](ivec2(1, 0), ivec2(1, 1), ivec2(0, 1), ivec2(-1, 1), ivec2(-1, 0), ivec2(-1, -1),
                                 ivec2(0, -1), ivec2(1, -1));
int around(ivec2 d) {
  if (d.y == 0) return d.x > 0 ? 0 : 4;
  if (d.x == 0) return d.y > 0 ? 2 : 6;
  return d.x == d.y ? (d.x > 0 ? 1 : 5) : (d.x > 0 ? 7 : 3);
}

// Whether the surface met in the directions marked in `hits` (bit k:
// direction k, around()) closes the half-turn on one side of a line whose
// bits are in `lines`: the pixel lies in the mouth of a notch of the
// surface (its sides the line's ends, its bottom the three directions
// between them), which a disk as wide as the gap could not enter: the
// closing of the surface's silhouette by the scan's spacing.
const int AXIS_LINES = 5;  // the horizontal and vertical lines' bits
bool closes_half_turn(int hits, int lines) {
  int turn = hits | (hits << 8);
  for (int k = 0; k < 4; ++k)
    if ((lines & (1 << k)) != 0 && (((turn >> k) & 31) == 31 || ((turn >> (k + 4)) & 31) == 31)) return true;
  return false;
}

struct Acc {
  vec4 sum;
  float weight, lo, hi;
  int lines;
  float depth;  // the weighted sum of the ends' depths
  int across;   // the enclosing lines: bit k for the line through directions k and k + 4 (around())
};

// Line `d` through p with first pixels a (along d) and b (against it): a
// gap of one surface when the ends' depths differ no more than its steepest
// slope allows over the gap, and on either side the surface runs on for at
// least half the gap (its splats are as wide as its gaps, not lone splats).
void line(ivec2 p, ivec2 d, Hit a, Hit b, float limit, inout Acc acc) {
  if (a.t == 0 || b.t == 0) return;
  float gap = float(a.t + b.t - 1);
  float across = (gap + 1.0) * length(vec2(d)) * pixel_size(min(a.depth, b.depth));  // view units
  if (abs(a.depth - b.depth) > across * u_grazing) return;
  // Between the scan's neighbours (the segment's spacing, else either
  // end's own), or between splats as wide as the gap.
  if (!(across <= u_span) && !(across <= max(span_at(p + a.t * d), span_at(p - b.t * d)))) {
    int need = (int(gap) + 1) / 2;
    if (a.t > u_splat_reach || b.t > u_splat_reach || 1 + run_length(p, d, a.t, limit, need - 1) < need ||
        1 + run_length(p, -d, b.t, limit, need - 1) < need)
      return;
  }
  float wa = 1.0 / float(a.t), wb = 1.0 / float(b.t);
  acc.sum += wa * a.color + wb * b.color;
  acc.depth += wa * a.depth + wb * b.depth;
  acc.weight += wa + wb;
  acc.lo = min(acc.lo, min(a.depth, b.depth));
  acc.hi = max(acc.hi, max(a.depth, b.depth));
  ++acc.lines;
  acc.across |= 1 << (around(d) & 3);
}

// Line `d` with first pixels a and b: where the two are a depth jump apart
// (the nearer surface's shadow, below), or the gap is one between the
// farther surface's own samples (no longer than twice the scan's spacing at
// that surface's depth), the farther surface runs on behind the nearer
// one's edge: it alone fills the background pixel, the nearer one's
// silhouette stays where it is. Returns the farther end's depth, or +inf
// when the line does not qualify.
float far_end(ivec2 p, ivec2 d, Hit a, Hit b) {
  if (a.t == 0 || b.t == 0) return INF;
  float far = max(a.depth, b.depth);
  float across = float(a.t + b.t) * length(vec2(d)) * pixel_size(far);
  // Or the nearer end's shadow: a scanner beside the camera (a depth
  // camera's projector, a laser's other station; up to 45 degrees off the
  // view) misses a band of what lies behind an edge as wide as the edge
  // stands in front of it. A gap no wider than its ends' depth step is such
  // a band (at any depth jump, whose step is more than the steepest slope
  // over the gap, within the search's reach): the farther end runs on
  // behind the edge and fills it.
  if (across <= far - min(a.depth, b.depth)) return far;
  return across <= u_span || across <= span_at(a.depth >= b.depth ? p + a.t * d : p - b.t * d) ? far : INF;
}

void far_line(float far, float lo, Hit a, Hit b, inout Acc acc) {
  if (isinf(far) || far < lo) return;
  Hit f = a.depth >= b.depth ? a : b;
  float w = 1.0 / float(f.t);
  acc.sum += w * f.color;
  acc.depth += w * f.depth;
  acc.weight += w;
  acc.lo = min(acc.lo, f.depth);
  acc.hi = max(acc.hi, f.depth);
  ++acc.lines;
}

// Whether pixel p (colour c) may change: a background pixel, or a covered
// one with a gap or a nearer surface near it. Everything else is copied.
bool needs_work(ivec2 p, vec4 c, out float own) {
  own = INF;
  if (any(lessThan(p, u_cover_min)) || any(greaterThanEqual(p, u_cover_max))) return false;
  own = covered(c) ? imageLoad(u_depth, p).r : INF;
  // Covered without depth (a filter's paint): kept as it is.
  if (covered(c) && isinf(own)) return false;
  if (!isinf(own)) {
    // A covered pixel can only be a back point seen through a gap where a
    // gap or a nearer surface lies 2 px away (a splat's width) along an
    // axis: most of a surface is not, and costs four loads.
    float step_limit = own - 4.0 * pixel_size(own) * u_grazing;
    ivec2 hi_corner = u_cover_max - 1;
    vec4 z = vec4(imageLoad(u_depth, clamp(p + ivec2(2, 0), u_cover_min, hi_corner)).r,
                  imageLoad(u_depth, clamp(p - ivec2(2, 0), u_cover_min, hi_corner)).r,
                  imageLoad(u_depth, clamp(p + ivec2(0, 2), u_cover_min, hi_corner)).r,
                  imageLoad(u_depth, clamp(p - ivec2(0, 2), u_cover_min, hi_corner)).r);
    if (!any(isinf(z)) && !any(lessThan(z, vec4(step_limit)))) return false;
  }
  return true;
}

// The longest gap between the scan's neighbours at hit h along d (0: none).
float spacing_of(ivec2 p, ivec2 d, Hit h) { return h.t > 0 ? span_at(p + h.t * d) : 0.0; }
Hit within_reach(Hit h) { return h.t > g_reach ? Hit(0, INF, vec4(0.0)) : h; }

void fill_pixel(ivec2 p, vec4 c, float own) {
  // The first pixels met along the 8 directions (one variable each: no
  // arrays); at least two lines must meet a surface on one side.
  const ivec2 D0 = ivec2(1, 0), D1 = ivec2(0, 1), D2 = ivec2(1, 1), D3 = ivec2(1, -1);
  g_reach = u_reach;
  Hit a0 = march(p, D0, own), a1 = march(p, D1, own), a2 = march(p, D2, own), a3 = march(p, D3, own);
  if (int(a0.t > 0) + int(a1.t > 0) + int(a2.t > 0) + int(a3.t > 0) < 2) return;  // fewer still within the reach
  Hit b0 = march(p, -D0, own), b1 = march(p, -D1, own), b2 = march(p, -D2, own), b3 = march(p, -D3, own);
  // The ends of a gap lie at most twice their points' spacing apart: the
  // search reaches that far (less a pixel) at the nearest depth met, and
  // no less than the segment's spacing reaches at its nearest depth.
  float met = min(min(min(a0.depth, a1.depth), min(a2.depth, a3.depth)),
                  min(min(b0.depth, b1.depth), min(b2.depth, b3.depth)));
  float span = max(max(max(spacing_of(p, D0, a0), spacing_of(p, D1, a1)),
                       max(spacing_of(p, D2, a2), spacing_of(p, D3, a3))),
                   max(max(spacing_of(p, -D0, b0), spacing_of(p, -D1, b1)),
                       max(spacing_of(p, -D2, b2), spacing_of(p, -D3, b3))));
  float size = pixel_size(met);
  g_reach = span > 0.0 && size > 0.0 ? int(clamp(ceil(span / size) - 1.0, float(u_reach_floor), float(u_reach)))
                                     : u_reach_floor;
  a0 = within_reach(a0), a1 = within_reach(a1), a2 = within_reach(a2), a3 = within_reach(a3);
  b0 = within_reach(b0), b1 = within_reach(b1), b2 = within_reach(b2), b3 = within_reach(b3);
  if (int(a0.t > 0) + int(a1.t > 0) + int(a2.t > 0) + int(a3.t > 0) < 2) return;
  // The first hits, for the farther surface's rule (far_end) where the
  // nearest surface does not enclose the pixel.
  float f0 = far_end(p, D0, a0, b0), f1 = far_end(p, D1, a1, b1), f2 = far_end(p, D2, a2, b2),
        f3 = far_end(p, D3, a3, b3);
  Hit fa0 = a0, fa1 = a1, fa2 = a2, fa3 = a3, fb0 = b0, fb1 = b1, fb2 = b2, fb3 = b3;
  float near = min(min(min(a0.depth, a1.depth), min(a2.depth, a3.depth)),
                   min(min(b0.depth, b1.depth), min(b2.depth, b3.depth)));
  // Hits beyond what the nearest surface reaches over the search (a back
  // surface seen through the same gap) are looked past.
  float limit = near + 2.0 * float(g_reach) * pixel_size(near) * u_grazing;
  if (a0.depth > limit && a0.t > 0) a0 = march(p, D0, limit);
  if (a1.depth > limit && a1.t > 0) a1 = march(p, D1, limit);
  if (a2.depth > limit && a2.t > 0) a2 = march(p, D2, limit);
  if (a3.depth > limit && a3.t > 0) a3 = march(p, D3, limit);
  if (b0.depth > limit && b0.t > 0) b0 = march(p, -D0, limit);
  if (b1.depth > limit && b1.t > 0) b1 = march(p, -D1, limit);
  if (b2.depth > limit && b2.t > 0) b2 = march(p, -D2, limit);
  if (b3.depth > limit && b3.t > 0) b3 = march(p, -D3, limit);
  Acc acc = Acc(vec4(0.0), 0.0, INF, 0.0, 0, 0.0, 0);
  line(p, D0, a0, b0, limit, acc);
  line(p, D1, a1, b1, limit, acc);
  line(p, D2, a2, b2, limit, acc);
  line(p, D3, a3, b3, limit, acc);
  vec4 sum = acc.sum;
  float weight = acc.weight, lo = acc.lo, hi = acc.hi, depth = acc.depth;
  int lines = acc.lines;
  if (lines == 1 && isinf(own)) {
    // One line encloses the pixel: a notch's mouth when the surface closes
    // the half-turn between its ends (every hit is the nearest surface's:
    // those beyond `limit` were looked past). A horizontal or vertical line
    // only: a diagonal march slips between two pixels that touch at a
    // corner, so along a 45 degree border every other diagonal line is
    // enclosed and a diagonal line's mouths would fill as stripes.
    int hits = int(a0.t > 0) | int(a2.t > 0) << 1 | int(a1.t > 0) << 2 | int(b3.t > 0) << 3 | int(b0.t > 0) << 4 |
               int(b2.t > 0) << 5 | int(b1.t > 0) << 6 | int(a3.t > 0) << 7;
    if (closes_half_turn(hits, acc.across & AXIS_LINES)) lines = 2;
  }
  if (lines >= 2 && !isinf(own)) {
    // A covered pixel gives way only to a surface it cannot belong to: one
    // nearer by more than that surface's steepest slope over the search and
    // more than twice the spread of its own enclosing pixels (the scan's
    // local noise).
    if (own <= limit || own - hi <= 2.0 * (hi - lo) + pixel_size(hi) * u_grazing) lines = 0;
  }
  if (lines < 2 && isinf(own)) {
    // The farthest of the lines' farther ends, and those one surface with
    // it (within its slope over the search).
    float far = max(max(isinf(f0) ? 0.0 : f0, isinf(f1) ? 0.0 : f1), max(isinf(f2) ? 0.0 : f2, isinf(f3) ? 0.0 : f3));
    float lo_far = far - 2.0 * float(g_reach) * pixel_size(far) * u_grazing;
    Acc back = Acc(vec4(0.0), 0.0, INF, 0.0, 0, 0.0, 0);
    far_line(f0, lo_far, fa0, fb0, back);
    far_line(f1, lo_far, fa1, fb1, back);
    far_line(f2, lo_far, fa2, fb2, back);
    far_line(f3, lo_far, fa3, fb3, back);
    if (back.lines >= 2) {
      sum = back.sum;
      weight = back.weight;
      depth = back.depth;
      lines = back.lines;
    }
  }
  imageStore(u_out, p, lines >= 2 ? sum / weight : c);
  // Filters after the fill read its depths (u_depth_out, a copy of u_depth
  // made before): a filled pixel lies on the surface that filled it.
  if (lines >= 2) imageStore(u_depth_out, p, vec4(depth / weight));
}

// Passes: SWEEP (4 dispatches) gives the marches from background pixels
// their hits; CLASSIFY copies every pixel and lists the pixels that need
// work; FILL runs the search on the listed pixels only, 64 to a group (dispatched
// indirectly from the list's count). llvmpipe runs every invocation of a
// shader holding the search at a cost even where no lane enters it, so the
// search runs on nothing else: not on tiles, whose other pixels paid it.
layout(std430, binding = 3) buffer Work {
  uint groups_x, groups_y, groups_z, count;
  uint pixels[];  // x | y << 16
};
// Each 16x16 tile's nearest depth (+inf: no point), tiles in rows of
// u_groups.x.
layout(std430, binding = 4) buffer TileDepth { float tile_depth[]; };
uniform ivec2 u_groups;
// Whether a pixel at depth `own` may give way to a surface whose nearest
// depth around its tile is `near`: fill_pixel keeps a covered pixel unless
// it lies beyond the limit of the surface enclosing it (that surface's
// nearest hit plus its slope over the search), and that limit is at least
// `near` plus the slope over the least reach (u_reach_floor) at the
// smallest pixel size between `near` and `own`.
// So a covered pixel searches only behind a depth jump, not everywhere on a
// surface with gaps (an aerial tile's scan lines), where its marches would
// run the whole reach through its own surface.
bool may_give_way(float own, float near) {
  if (isinf(own)) return true;
  float a = u_surface_x0.x + near * u_surface_x1.x, b = u_surface_x0.x + own * u_surface_x1.x;
  float size = a * b > 0.0 ? min(abs(a), abs(b)) : 0.0;
  float bound = near + 2.0 * float(u_reach_floor) * size * u_grazing;  // the least reach
  return own > bound - 1e-5 * abs(bound);  // a margin for rounding: only surely kept pixels skip
}
#ifdef PASS_SWEEP
// One invocation per line of orientation u_orientation through the covered
// box, in one walk along it: a shift register of the last 32 pixels' hits
// gives the pixel 16 back its distances to the nearest hit ahead (within
// the register) and behind (a counter). Line l starts on the box's first
// column (columns: its first row) or, for the diagonals, also on its first
// (antidiagonals: last) row.
uniform int u_orientation;
layout(local_size_x = 64) in;
void main() {
  ivec2 size = u_cover_max - u_cover_min;
  int l = int(gl_GlobalInvocationID.x);
  ivec2 dir = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1))[u_orientation];
  ivec2 start;
  int lines_a = u_orientation == 1 ? size.x : size.y;  // lines starting on the first column (row)
  if (u_orientation == 1) start = ivec2(l, 0);
  else if (l < size.y) start = ivec2(0, l);
  else if (u_orientation == 2) start = ivec2(l - size.y + 1, 0);
  else start = ivec2(l - size.y + 1, size.y - 1);
  if (l >= lines_a + (u_orientation >= 2 ? size.x - 1 : 0)) return;
  // Steps until the line leaves the box.
  int len = u_orientation == 0 ? size.x : u_orientation == 1 ? size.y
          : min(size.x - start.x, u_orientation == 2 ? size.y - start.y : start.y + 1);
  start += u_cover_min;
  uint reg = 0u, behind = 0u;  // bit i of reg: the hit at k - i
  for (int k = 0; k < len + 16; ++k) {
    ivec2 q = start + k * dir;
    reg = (reg << 1) | (k < len && imageLoad(u_depth, q).r < INF && covered(imageLoad(u_in, q)) ? 1u : 0u);
    int j = k - 16;
    if (j < 0) continue;
    uint ahead = reg & 0xffffu;  // bit i: the hit at j + 16 - i
    uint to_ahead = ahead == 0u ? 0u : uint(16 - findMSB(ahead));
    imageStore(u_runs, ivec3(start + j * dir, u_orientation), uvec4(to_ahead, behind, 0u, 0u));
    behind = ((reg >> 16) & 1u) != 0u ? 1u : (behind == 0u || behind >= 16u ? 0u : behind + 1u);
  }
}
#elif defined(PASS_SPECK)
// After the search: a background pixel with at least 6 of its 8 neighbours
// covered by one surface (their depths within its slope over two pixels) is
// a pinhole the lines missed (a scan's lattice of lone splats leaves some
// that no two lines reach), and one with 5 of them side by side the bottom
// of a notch a pixel wide (closes_half_turn): it takes their mean. Reads
// the fill's colours (u_in) and writes a copy of them (u_out); the depths
// in place (u_depth and u_depth_out are one image): only background pixels
// are written and only covered ones read.
layout(local_size_x = 16, local_size_y = 16) in;
void main() {
  ivec2 p;
  if (!rect_pixel(p) || covered(imageLoad(u_in, p))) return;
  vec4 sum = vec4(0.0);
  float depth = 0.0, lo = INF, hi = 0.0;
  int n = 0, hits = 0;
  for (int k = 0; k < 8; ++k) {
    ivec2 q = p + AROUND[k];
    vec4 c = imageLoad(u_in, q);
    if (!covered(c)) continue;
    float d = imageLoad(u_depth, q).r;
    if (isinf(d)) continue;  // a filter's paint, no surface
    sum += c;
    depth += d;
    lo = min(lo, d);
    hi = max(hi, d);
    ++n;
    hits |= 1 << k;
  }
  if ((n < 6 && !closes_half_turn(hits, 15)) || hi - lo > 2.0 * pixel_size(lo) * u_grazing) return;
  imageStore(u_out, p, sum / float(n));
  imageStore(u_depth_out, p, vec4(depth / float(n)));
}
#elif defined(PASS_CLASSIFY)
layout(local_size_x = 16, local_size_y = 16) in;
// A background pixel can change only where at least 2 of its 4 lines meet
// a covered pixel within the reach on both sides (fill_pixel's lines): the
// background around a surface is not listed.
// Or one line does and the surface closes the half-turn on one side of it
// (a notch's mouth: closes_half_turn).
bool enclosed(ivec2 p) {
  int lines = 0, across = 0, hits = 0;
  // Orientation o's ahead and behind, as directions around(): horizontal
  // 0 and 4, vertical 2 and 6, diagonal 1 and 5, antidiagonal 7 and 3.
  const ivec4 AHEAD = ivec4(0, 2, 1, 7), BEHIND = ivec4(4, 6, 5, 3);
  for (int o = 0; o < 4; ++o) {
    uvec2 run = imageLoad(u_runs, ivec3(p, o)).rg;
    bool ahead = run.r != 0u && run.r <= uint(u_reach), behind = run.g != 0u && run.g <= uint(u_reach);
    hits |= int(ahead) << AHEAD[o] | int(behind) << BEHIND[o];
    if (ahead && behind) {
      ++lines;
      across |= 1 << (AHEAD[o] & 3);
    }
  }
  return lines >= 2 || closes_half_turn(hits, across & AXIS_LINES);
}
shared uint s_count, s_base;
shared uint s_near;  // float bits: positive floats order as their bits do
void main() {
  if (gl_LocalInvocationIndex == 0u) {
    s_count = 0u;
    s_near = floatBitsToUint(INF);
  }
  barrier();
  ivec2 p;
  bool work = false;
  uint slot = 0u;
  if (rect_pixel(p)) {
    vec4 c = imageLoad(u_in, p);
    imageStore(u_out, p, c);
    float own;
    work = needs_work(p, c, own) && (covered(c) || enclosed(p));
    if (work) slot = atomicAdd(s_count, 1u);
    float d = imageLoad(u_depth, p).r;
    if (d >= 0.0 && d < INF) atomicMin(s_near, floatBitsToUint(d));
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    tile_depth[gl_WorkGroupID.y * uint(u_groups.x) + gl_WorkGroupID.x] = uintBitsToFloat(s_near);
    s_base = atomicAdd(count, s_count);
    // At most 65535 groups (GL's least limit): the search strides over a
    // longer list.
    atomicMax(groups_x, min((s_base + s_count + 63u) / 64u, 65535u));
  }
  barrier();
  if (work) pixels[s_base + slot] = uint(p.x) | (uint(p.y) << 16);
}
#else
layout(local_size_x = 64) in;
void main() {
  // One loop around the search, no early returns: llvmpipe runs code
  // after a return masked, but skips a branch no lane takes.
  for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * 64u) {
    ivec2 p = ivec2(pixels[i] & 0xffffu, pixels[i] >> 16);
    vec4 c = imageLoad(u_in, p);
    float own = covered(c) ? imageLoad(u_depth, p).r : INF;  // as needs_work found it
    // A background pixel was listed for the surface its lines meet. A
    // covered one searches only where it may give way to the nearest
    // surface around it: the ends of a gap lie within u_reach <= 16 px, in
    // the pixel's tile or the 8 around it.
    bool search = isinf(own);
    if (!search) {
      ivec2 t = (p - u_rect_min) / 16;
      float near = INF;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          ivec2 q = t + ivec2(dx, dy);
          if (all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, u_groups)))
            near = min(near, tile_depth[q.y * u_groups.x + q.x]);
        }
      search = !isinf(near) && may_give_way(own, near);
    }
    if (search) fill_pixel(p, c, own);
  }
}
#endif
