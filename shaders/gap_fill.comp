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
    float d = imageLoad(u_depth, q).r;  // +inf where no point is
    if (d < behind) {
      vec4 c = imageLoad(u_in, q);
      if (covered(c)) {
        h.t = k;
        h.depth = d;
        h.color = c;
        return h;
      }
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

// The lines through a pixel: horizontal, vertical, both diagonals (no
// arrays: llvmpipe pays for local arrays in every invocation).
ivec2 line_dir(int i) { return i == 0 ? ivec2(1, 0) : i == 1 ? ivec2(0, 1) : i == 2 ? ivec2(1, 1) : ivec2(1, -1); }

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
    if (!any(isinf(z)) && !any(lessThan(z, vec4(step_limit)))) {
      imageStore(u_out, p, c);
      return;
    }
  }
  // The nearest surface met along the 8 directions; at least two lines must
  // meet a surface on one side.
  float near = INF;
  int sides = 0;
  for (int i = 0; i < 4; ++i) {
    Hit a = march(p, line_dir(i), own);
    sides += a.t > 0 ? 1 : 0;
    near = min(near, a.depth);
  }
  if (sides < 2) {
    imageStore(u_out, p, c);
    return;
  }
  for (int i = 0; i < 4; ++i) near = min(near, march(p, -line_dir(i), own).depth);
  // Hits beyond what the nearest surface reaches over the search (a back
  // surface seen through the same gap) are looked past.
  float limit = near + 2.0 * float(u_reach) * pixel_size(near) * u_grazing;
  float behind = min(own, limit);
  vec4 sum = vec4(0.0);
  float weight = 0.0, lo = INF, hi = 0.0;
  int lines = 0;
  for (int i = 0; i < 4; ++i) {
    ivec2 d = line_dir(i);
    Hit a = march(p, d, behind);
    if (a.t == 0) continue;
    Hit b = march(p, -d, behind);
    if (b.t == 0) continue;
    float step = length(vec2(d));
    float gap = float(a.t + b.t - 1);
    // One surface: the ends' depths differ no more than its steepest slope
    // allows over the gap.
    if (abs(a.depth - b.depth) > (gap + 1.0) * step * pixel_size(min(a.depth, b.depth)) * u_grazing) continue;
    // A gap of the surface, not beside a lone splat: on either side the
    // surface runs on for at least half the gap (its splats are as wide as
    // its gaps).
    int need = (int(gap) + 1) / 2;
    if (1 + run_length(p, d, a.t, limit, need - 1) < need || 1 + run_length(p, -d, b.t, limit, need - 1) < need)
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
