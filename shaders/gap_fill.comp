// Depth-aware gap fill before the filters that read neighbourhoods
// (cpp/render/filter_chain.cpp). A pixel is a gap of a surface when that
// surface's own pixels enclose it: along at least 3 of the 4 lines through
// it (horizontal, vertical, both diagonals) the first pixel of the surface
// lies within u_reach on both sides, and the two ends are one surface: their
// depths differ by no more than a surface seen at the steepest angle
// (u_grazing = tan of it) can change over the gap, the gap's length times
// the pixel's footprint at that depth. Covered pixels count as gaps too
// when a surface nearer than them by more than that, and more than twice
// the depth spread of its own enclosing pixels (the scan's local noise),
// encloses them: back points seen through the gaps of a front surface.
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

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  if (any(lessThan(p, u_cover_min)) || any(greaterThanEqual(p, u_cover_max))) {
    imageStore(u_out, p, c);
    return;
  }
  float own = covered(c) ? imageLoad(u_depth, p).r : INF;
  if (isinf(own)) own = covered(c) ? -1.0 : INF;  // covered without depth (a filter's paint): keep
  const ivec2 dirs[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1));
  vec4 sum = vec4(0.0);
  float weight = 0.0, near = INF, far = 0.0;
  int lines = 0, failed = 0;
  for (int i = 0; i < 4 && own > 0.0 && failed < 3; ++i) {
    Hit a = march(p, dirs[i], own);
    Hit b = a.t > 0 ? march(p, -dirs[i], own) : a;
    bool ok = a.t > 0 && b.t > 0;
    if (ok) {
      float len = float(a.t + b.t) * length(vec2(dirs[i]));
      float dmin = min(a.depth, b.depth);
      ok = abs(a.depth - b.depth) <= len * pixel_size(dmin) * u_grazing;
    }
    if (!ok) {
      ++failed;
      continue;
    }
    ++lines;
    float wa = 1.0 / float(a.t), wb = 1.0 / float(b.t);
    sum += wa * a.color + wb * b.color;
    weight += wa + wb;
    near = min(near, min(a.depth, b.depth));
    far = max(far, max(a.depth, b.depth));
  }
  if (lines >= 2 && !isinf(own)) {
    // A covered pixel: only behind the enclosing surface by more than its
    // own spread and the steepest slope over one pixel.
    float gap = own - far;
    if (gap <= 2.0 * (far - near) + pixel_size(far) * u_grazing) lines = 0;
  }
  imageStore(u_out, p, lines >= 2 ? sum / weight : c);
}
