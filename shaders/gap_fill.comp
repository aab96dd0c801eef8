// Depth-aware gap fill before the filters that read neighbourhoods
// (cpp/render/filter_chain.cpp). A pixel is a gap of a surface when that
// surface's own pixels enclose it: along at least 3 of the 4 lines through
// it (horizontal, vertical, both diagonals) the first pixel of the surface
// lies within u_reach on both sides, and the two ends are one surface: their
// depths differ by no more than a surface seen at the steepest angle
// (u_grazing = tan of it) can change over the gap, the gap's length times
// the pixel's footprint at that depth, and on either side the surface runs
// on for at least half the gap (its splats are as wide as its gaps: lone
// splats do not merge, nor join a surface). Covered pixels count as gaps too when a surface
// nearer than them by more than its slope over the whole search, and more
// than twice the depth spread of its own enclosing pixels (the scan's
// local noise), encloses them: back points seen through a front surface.
// A gap takes the inverse-distance mean of its enclosing pixels (rgba,
// straight alpha). Nothing crosses a depth jump: the background beside a
// silhouette, or a far wall seen past an edge, is enclosed by no surface.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(r32f, binding = 2) uniform readonly image2D u_depth;
uniform int u_reach;
uniform float u_grazing;
uniform ivec2 u_cover_min;  // covered pixels lie within [u_cover_min, u_cover_max)
uniform ivec2 u_cover_max;

// Scene units one pixel spans at depth d (the view-space x of pixel q at
// depth d is dot(x0, q) + d dot(x1, q): filter_common.glsl).
float pixel_size(float d) { return abs(u_surface_x0.x + d * u_surface_x1.x); }

struct Hit {
  int t;  // 0: none within reach
  float depth;
  vec4 color;
};

// The first pixel along `dir` nearer than `behind` (covered, finite depth).
Hit march(ivec2 p, ivec2 dir, float behind) {
  Hit h = Hit(0, INF, vec4(0.0));
  for (int k = 1; k <= u_reach; ++k) {
    ivec2 q = p + k * dir;
    if (any(lessThan(q, u_cover_min)) || any(greaterThanEqual(q, u_cover_max))) return h;
    float d = imageLoad(u_depth, q).r;
    vec4 c = imageLoad(u_in, q);
    if (covered(c) && d < behind) {
      h.t = k;
      h.depth = d;
      h.color = c;
      return h;
    }
  }
  return h;
}

// How many covered pixels nearer than `limit` (the surface, not what lies
// behind it) follow the hit at `t` along `dir`, up to `cap`.
int run_length(ivec2 p, ivec2 dir, int t, float limit, int cap) {
  int n = 0;
  for (int k = t + 1; k <= t + cap; ++k) {
    ivec2 q = p + k * dir;
    if (any(lessThan(q, u_cover_min)) || any(greaterThanEqual(q, u_cover_max))) break;
    if (!covered(imageLoad(u_in, q)) || !(imageLoad(u_depth, q).r <= limit)) break;
    ++n;
  }
  return n;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (any(lessThan(p, u_cover_min)) || any(greaterThanEqual(p, u_cover_max))) {
    imageStore(u_out, p, c);
    return;
  }
  float own = covered(c) ? imageLoad(u_depth, p).r : INF;
  // Covered without depth (a filter's paint): kept as it is.
  if (covered(c) && isinf(own)) {
    imageStore(u_out, p, c);
    return;
  }
  const ivec2 dirs[8] = ivec2[8](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1), ivec2(-1, 0), ivec2(0, -1),
                                 ivec2(-1, -1), ivec2(-1, 1));
  Hit h[8];
  int sides = 0;
  for (int k = 0; k < 4; ++k) {
    h[k] = march(p, dirs[k], own);
    sides += h[k].t > 0 ? 1 : 0;
  }
  if (sides < 2) {  // two lines enclose the pixel at least
    imageStore(u_out, p, c);
    return;
  }
  for (int k = 4; k < 8; ++k) h[k] = h[k - 4].t > 0 ? march(p, dirs[k], own) : Hit(0, INF, vec4(0.0));
  // The nearest surface met: hits beyond what it can reach over the search
  // (a back surface seen through the same gap) are looked past.
  float near = INF;
  for (int k = 0; k < 8; ++k) near = min(near, h[k].depth);
  float limit = near + 2.0 * float(u_reach) * pixel_size(near) * u_grazing;
  for (int k = 0; k < 8; ++k)
    if (h[k].t > 0 && h[k].depth > limit) h[k] = march(p, dirs[k], limit);
  vec4 sum = vec4(0.0);
  float weight = 0.0, lo = INF, hi = 0.0;
  int lines = 0;
  for (int i = 0; i < 4; ++i) {
    Hit a = h[i], b = h[i + 4];
    if (a.t == 0 || b.t == 0) continue;
    float step = length(vec2(dirs[i]));
    float gap = float(a.t + b.t - 1);
    // One surface: the ends' depths differ no more than its steepest slope
    // allows over the gap.
    if (abs(a.depth - b.depth) > (gap + 1.0) * step * pixel_size(min(a.depth, b.depth)) * u_grazing) continue;
    // A gap of the surface, not beside a lone splat: on either side the
    // surface runs on for at least half the gap (its splats are as wide as
    // its gaps).
    int need = (int(gap) + 1) / 2;
    if (1 + run_length(p, dirs[i], a.t, limit, need - 1) < need ||
        1 + run_length(p, dirs[i + 4], b.t, limit, need - 1) < need)
      continue;
    ++lines;
    float wa = 1.0 / float(a.t), wb = 1.0 / float(b.t);
    sum += wa * a.color + wb * b.color;
    weight += wa + wb;
    lo = min(lo, min(a.depth, b.depth));
    hi = max(hi, max(a.depth, b.depth));
  }
  if (lines >= 2 && !isinf(own)) {
    // A covered pixel gives way only to a surface it cannot belong to: one
    // nearer by more than that surface's steepest slope over the search and
    // more than twice the spread of its own enclosing pixels (the scan's
    // local noise).
    if (own <= limit || own - hi <= 2.0 * (hi - lo) + pixel_size(hi) * u_grazing) lines = 0;
  }
  imageStore(u_out, p, lines >= 2 ? sum / weight : c);
}
