// Edge enhancement (cpp/filters/edge_enhance.cpp).
// variants: | PASS_NORMALS
// PASS_NORMALS (only with creases on): surface normals from the depth-plane
//   fit, to a scratch image (xyz, w = 1 where valid).
// Main pass: eye-dome lighting, depth-discontinuity and crease lines,
//   silhouettes of dense regions.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
layout(r32f, binding = 2) uniform readonly image2D u_depth;
uniform float u_edl_strength;
uniform float u_edl_radius;
uniform int u_outline_width;
uniform float u_depth_threshold;
uniform int u_silhouette;
uniform int u_fill;
uniform float u_density;
uniform vec4 u_edge_color;
uniform float u_crease_cos;  // lines where normals differ by more (cos of the angle); > 1 = off
// Depth differences up to this (view units) are the scan's own noise, not
// relief: the scan's spacing (ScanSampling), 0 where unknown.
uniform float u_depth_floor;
#include "surface_fit.glsl"

#ifdef PASS_NORMALS
layout(rgba32f, binding = 3) uniform writeonly image2D u_normals_out;
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  SurfacePatch s = fit_surface(p, 2);
  vec3 n = s.valid ? cross(s.dPdx, s.dPdy) : vec3(0.0);
  float len = length(n);
  imageStore(u_normals_out, p, len > 0.0 ? vec4(n / len, 1.0) : vec4(0.0));
}
#else
layout(rgba32f, binding = 3) uniform readonly image2D u_normals;

// Linear depth of a covered pixel with depth, else +inf.
float depth_at(ivec2 q) {
  if (!in_image(q, imageSize(u_in)) || !covered(imageLoad(u_in, q))) return INF;
  return imageLoad(u_depth, q).x;
}

// One EDL neighbour, `radius` away along lattice direction `dir` (an axis
// or a diagonal): max(0, lz - log2(z + u_depth_floor)) (a neighbour counts
// as nearer only by what it is nearer beyond the scan's noise, so a
// Kinect wall's depth steps shade nothing) interpolated linearly
// between the two pixels along `dir` that bracket that distance, so the
// radius acts continuously rather than in whole pixels (1 and 1.4 px used
// to round to the same neighbours), and flat depth gives exactly 0; -1
// where neither pixel has depth.
float edl_neighbour(ivec2 p, ivec2 dir, float radius, float lz) {
  float t = radius / length(vec2(dir));
  float k = floor(t), f = t - k;
  // Depth alone: +inf where nothing was drawn; outside the image, 0.
  vec2 z = vec2(imageLoad(u_depth, p + int(k) * dir).x, imageLoad(u_depth, p + int(k + 1.0) * dir).x);
  bvec2 valid = bvec2(uvec2(greaterThan(z, vec2(0.0))) * uvec2(not(isinf(z))));
  vec2 w = mix(vec2(0.0), vec2(1.0 - f, f), valid);
  vec2 terms = mix(vec2(0.0), max(vec2(0.0), lz - log2(max(z + u_depth_floor, vec2(1e-30)))), valid);
  float weight = w.x + w.y;
  return weight > 1e-6 ? dot(w, terms) / weight : -1.0;
}

float covered_fraction(ivec2 q) {
  int n = 0;
  ivec2 size = imageSize(u_in);
  for (int dy = -u_fill; dy <= u_fill; ++dy)
    for (int dx = -u_fill; dx <= u_fill; ++dx) {
      ivec2 r = q + ivec2(dx, dy);
      n += in_image(r, size) && covered(imageLoad(u_in, r)) ? 1 : 0;
    }
  return float(n) / float((2 * u_fill + 1) * (2 * u_fill + 1));
}

bool surface(ivec2 q) {
  return in_image(q, imageSize(u_in)) && covered(imageLoad(u_in, q)) && covered_fraction(q) >= u_density;
}

// How much the surface turns across q along e: 1 - cos of the angle
// between the normals CREASE_STEP pixels on either side, where both sides
// are the same surface as q (no depth jump). The normals come from 5x5
// plane fits, so sampling them 3 px apart compares the pure sides of a
// crease rather than fits straddling it.
const int CREASE_STEP = 3;
float crease_strength(ivec2 q, ivec2 e, float zq) {
  ivec2 a = q - CREASE_STEP * e, b = q + CREASE_STEP * e;
  if (!in_image(a, imageSize(u_in)) || !in_image(b, imageSize(u_in))) return 0.0;
  vec4 na = imageLoad(u_normals, a), nb = imageLoad(u_normals, b);
  float za = depth_at(a), zb = depth_at(b);
  if (na.w <= 0.0 || nb.w <= 0.0 || abs(za - zq) > u_depth_threshold * zq || abs(zb - zq) > u_depth_threshold * zq)
    return 0.0;
  return 1.0 - dot(na.xyz, nb.xyz);
}

// A crease passes through q: the turn across q, along one of four
// directions, exceeds the crease angle and is a local maximum along that
// direction (non-maximum suppression: one pixel wide).
bool crease_at(ivec2 q) {
  float zq = depth_at(q);
  if (isinf(zq)) return false;
  const ivec2 dirs[4] = ivec2[4](ivec2(1, 0), ivec2(0, 1), ivec2(1, 1), ivec2(1, -1));
  for (int i = 0; i < 4; ++i) {
    float c = crease_strength(q, dirs[i], zq);
    if (c > 1.0 - u_crease_cos && c >= crease_strength(q - dirs[i], dirs[i], zq) &&
        c >= crease_strength(q + dirs[i], dirs[i], zq))
      return true;
  }
  return false;
}

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec4 c = imageLoad(u_in, p);
  int w = u_outline_width;
  if (covered(c)) {
    float z = depth_at(p);
    if (isinf(z)) {
      imageStore(u_out, p, c);
      return;
    }
    // Eye-dome lighting on log depth; background neighbours add nothing.
    float lz = log2(z), response = 0.0;
    const ivec2 dirs8[8] = ivec2[8](ivec2(1, 0), ivec2(1, 1), ivec2(0, 1), ivec2(-1, 1), ivec2(-1, 0),
                                    ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1));
    for (int i = 0; i < 8; ++i) response += max(0.0, edl_neighbour(p, dirs8[i], u_edl_radius, lz));
    float shade = exp(-response / 8.0 * 300.0 * u_edl_strength);
    vec3 rgb = c.rgb * shade;
    // A nearer surface within w: this pixel lies just behind a contour.
    float nearest = 1e9;
    for (int dy = -w; dy <= w; ++dy)
      for (int dx = -w; dx <= w; ++dx) {
        float d = length(vec2(dx, dy));
        if (d > float(w) + 0.5 || d >= nearest) continue;
        float zq = depth_at(p + ivec2(dx, dy));
        if (zq < min(z * (1.0 - u_depth_threshold), z - u_depth_floor)) nearest = d;
      }
    // A crease within w - 1 pixels (lines w wide, like the contours).
    if (nearest >= 1e9 && u_crease_cos <= 1.0) {
      int r = w - 1;
      for (int dy = -r; dy <= r && nearest >= 1e9; ++dy)
        for (int dx = -r; dx <= r; ++dx)
          if (length(vec2(dx, dy)) <= float(r) + 0.5 && crease_at(p + ivec2(dx, dy))) {
            nearest = 0.0;
            break;
          }
    }
    if (nearest < 1e9) rgb = mix(rgb, u_edge_color.rgb, u_edge_color.a);
    imageStore(u_out, p, vec4(rgb, c.a));
    return;
  }
  // Background: a silhouette line next to a dense region, unless this pixel
  // is a hole inside one.
  if (u_silhouette != 0 && w > 0 && covered_fraction(p) < 0.5) {
    for (int dy = -w; dy <= w; ++dy)
      for (int dx = -w; dx <= w; ++dx) {
        if (length(vec2(dx, dy)) > float(w) + 0.5) continue;
        if (surface(p + ivec2(dx, dy))) {
          imageStore(u_out, p, u_edge_color);
          return;
        }
      }
  }
  imageStore(u_out, p, c);
}
#endif
