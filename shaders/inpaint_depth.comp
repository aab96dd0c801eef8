// Depth inpainting in one pass.
//
// method 0, surface (the default): a pixel the segment's points cover keeps
// their depth, whatever the filters did to its colour (Listing 1 moved such
// pixels to a mean that crosses the depth discontinuities inside a segment:
// a crown in front of a wall, eaves over a facade). A pixel the filters
// added (covered now, not by the points) gets the depth of the nearest
// surface among its covered neighbours: the mean of those within
// `u_discontinuity` (relative) of the nearest one, never a mean across a
// depth jump. An outline thus lies in front of what is behind its surface.
//
// method 2, strict: as surface, but paint beyond the surface's silhouette
// never covers another segment's points (only holes the surface encloses
// compete by depth): never worse than the depth test against an
// unfiltered reference, at the cost of outlines over other segments.
// Such pixels are stored negated; compositing lets them win over empty
// pixels and other marked ones by depth, never over points.
//
// method 1, paper (Wegen et al. 2024, Listing 1): pixels whose gray level or
// coverage the filters changed get the mean depth of the covered pixels in
// a circle. Fixes over the listing: coverage changes count (a black outline
// on an empty background has no gray difference), a pixel the filters
// erased becomes background, and a pixel with no covered neighbour keeps
// its own depth instead of dividing by zero.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_raster_color;
layout(rgba32f, binding = 1) uniform readonly image2D u_filtered_color;
layout(r32f, binding = 2) uniform readonly image2D u_raster_depth;
layout(r32f, binding = 3) uniform writeonly image2D u_depth_out;
uniform float u_threshold;
uniform int u_radius;
uniform int u_method;          // 0 surface, 1 paper, 2 strict
uniform float u_discontinuity; // surface: relative depth gap between surfaces

// Surface method: the nearest surface's depth among the covered pixels of
// the circle (INF when none is covered), and whether that surface encloses
// the pixel: it is met along at least 7 of 8 directions within the radius
// (a hole between sparse points, not paint beyond the silhouette).
float nearest_surface_depth(ivec2 p, out bool enclosed) {
  ivec2 size = imageSize(u_raster_depth);
  int r2 = u_radius * u_radius;
  float nearest = INF;
  for (int dy = -u_radius; dy <= u_radius; ++dy)
    for (int dx = -u_radius; dx <= u_radius; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (dx * dx + dy * dy > r2 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      nearest = min(nearest, imageLoad(u_raster_depth, q).r);
    }
  enclosed = false;
  if (isinf(nearest)) return INF;
  float limit = nearest * (1.0 + u_discontinuity), sum = 0.0, count = 0.0;
  for (int dy = -u_radius; dy <= u_radius; ++dy)
    for (int dx = -u_radius; dx <= u_radius; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (dx * dx + dy * dy > r2 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      float d = imageLoad(u_raster_depth, q).r;
      if (d <= limit) {
        sum += d;
        count += 1.0;
      }
    }
  int hits = 0;
  for (int k = 0; k < 8; ++k) {
    ivec2 dir = ivec2(round(vec2(cos(0.785398 * float(k)), sin(0.785398 * float(k)))));
    for (int step = 1; step * step * (dir.x * dir.x + dir.y * dir.y) <= r2; ++step) {
      ivec2 q = p + dir * step;
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) break;
      if (imageLoad(u_raster_depth, q).r <= limit) {
        ++hits;
        break;
      }
    }
  }
  enclosed = hits >= 7;
  return sum / count;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 raster = imageLoad(u_raster_color, p);
  vec4 filtered = imageLoad(u_filtered_color, p);
  float depth = imageLoad(u_raster_depth, p).r;
  if (filtered.a <= 0.0) {
    imageStore(u_depth_out, p, vec4(INF));
    return;
  }
  if (u_method != 1) {
    if (isinf(depth)) {
      bool enclosed;
      float surface = nearest_surface_depth(p, enclosed);
      // strict: negative marks paint beyond the surface (it never covers
      // another segment's points).
      depth = u_method == 2 && !enclosed ? -surface : surface;
    }
    imageStore(u_depth_out, p, vec4(depth));
    return;
  }
  float change = max(abs(luminance(raster.rgb) * raster.a - luminance(filtered.rgb) * filtered.a),
                     abs(raster.a - filtered.a));
  if (change > u_threshold) {
    ivec2 size = imageSize(u_raster_depth);
    float sum = 0.0, count = 0.0;
    int r2 = u_radius * u_radius;
    for (int dy = -u_radius; dy <= u_radius; ++dy) {
      for (int dx = -u_radius; dx <= u_radius; ++dx) {
        ivec2 q = p + ivec2(dx, dy);
        if (dx * dx + dy * dy > r2 || any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
        float d = imageLoad(u_raster_depth, q).r;
        if (d < INF) {
          sum += d;
          count += 1.0;
        }
      }
    }
    if (count > 0.0) depth = sum / count;
  }
  imageStore(u_depth_out, p, vec4(depth));
}
