// Edge enhancement (cpp/filters/edge_enhance.cpp), one pass: eye-dome
// lighting, depth-discontinuity lines and silhouettes of dense regions.
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

// Linear depth of a covered pixel with depth, else +inf.
float depth_at(ivec2 q) {
  if (!in_image(q, imageSize(u_in)) || !covered(imageLoad(u_in, q))) return INF;
  return imageLoad(u_depth, q).x;
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
    for (int i = 0; i < 8; ++i) {
      float a = 0.78539816 * float(i);
      ivec2 q = p + ivec2(round(u_edl_radius * vec2(cos(a), sin(a))));
      float zq = depth_at(q);
      if (!isinf(zq)) response += max(0.0, lz - log2(zq));
    }
    float shade = exp(-response / 8.0 * 300.0 * u_edl_strength);
    vec3 rgb = c.rgb * shade;
    // A nearer surface within w: this pixel lies just behind a contour.
    float nearest = 1e9;
    for (int dy = -w; dy <= w; ++dy)
      for (int dx = -w; dx <= w; ++dx) {
        float d = length(vec2(dx, dy));
        if (d > float(w) + 0.5 || d >= nearest) continue;
        float zq = depth_at(p + ivec2(dx, dy));
        if (zq < z * (1.0 - u_depth_threshold)) nearest = d;
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
