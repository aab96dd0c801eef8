// Depth inpainting (Wegen et al. 2024, Listing 1) in one pass: pixels whose
// gray level or coverage the filters changed get the mean depth of the
// covered pixels in a circle. Fixes over the listing: coverage changes count
// (a black outline on an empty background has no gray difference), a pixel
// the filters erased becomes background, and a pixel with no covered
// neighbour keeps its own depth instead of dividing by zero.
#include "common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_raster_color;
layout(rgba32f, binding = 1) uniform readonly image2D u_filtered_color;
layout(r32f, binding = 2) uniform readonly image2D u_raster_depth;
layout(r32f, binding = 3) uniform writeonly image2D u_depth_out;
uniform float u_threshold;
uniform int u_radius;

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
