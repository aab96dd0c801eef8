// The points mark (cpp/marks/points.cpp): per-point setup shared by the
// compute rasterizer and the GL_POINTS path.
#include "point_attributes.glsl"
#include "id_hash.glsl"

// Each point's SplatRadius (cpp/marks/points/points.cpp): a Gaussian
// splat's footprint, a plain point's spacing (size_mode splat, spacing); a
// capture's opacity as the chance it is drawn.
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 7) readonly buffer SplatRadii { float splat_radius[]; };
layout(std430, binding = 8) readonly buffer SplatOpacities { float splat_opacity[]; };
uniform int u_opacity_draws;  // 1: drawn where id_rand(point id) < the splat's opacity
// 1: each pixel's point's spacing is written for the gap fill (its
// SplatRadius, scaled to view units by u_spacing_scale).
uniform int u_write_spacing;
uniform float u_spacing_scale;
float point_spacing(uint index) { return u_write_spacing != 0 ? splat_radius[index] * u_spacing_scale : 0.0; }
const uint kOpacitySalt = 0x6f706163u;  // id_rand's salt for the draw (native.cpp: the same)

uniform mat4 u_projection;
uniform ivec2 u_size;         // the frame's (the projection maps to it)
uniform float u_near;
uniform float u_far;
uniform int u_ortho;
uniform int u_size_mode;      // 0 pixels, 1 world, 2 each point's SplatRadius (world) x u_radius_diameters
uniform float u_radius_diameters;  // 2: a Gaussian splat's footprint; 1: the point's spacing (size_mode spacing)
uniform float u_min_size;          // pixels: size_mode spacing's point_size, else 0
uniform float u_point_size;
uniform float u_world_size;
uniform float u_px_per_unit;  // pixels per scene unit at view depth 1
uniform float u_max_size;
uniform ivec4 u_clip_rect;
uniform int u_shading;           // 0 none, 1 diffuse
uniform float u_shading_strength;
uniform vec3 u_light_dir;        // towards the light, view space

struct Splat {
  vec2 center;     // window coordinates (pixels)
  float depth;     // linear view depth
  float diameter;  // pixels
  bool visible;
};

Splat project_point(uint index) {
  Splat s;
  vec4 v = u_view_from_chunk * vec4(point_position(index), 1.0);
  s.depth = -v.z;
  s.visible = s.depth >= u_near && s.depth <= u_far;
  vec4 clip = u_projection * v;
  // precise: no fused multiply-add, the same bits whatever u_origin a tile subtracts.
  precise vec2 center = (clip.xy / clip.w * 0.5 + 0.5) * vec2(u_size);
  s.center = center;
  float w = u_ortho != 0 ? 1.0 : s.depth;
  float units = u_size_mode == 2 ? u_radius_diameters * splat_radius[index] : u_world_size;
  s.diameter = u_size_mode == 0 ? u_point_size : max(clamp(units * u_px_per_unit / w, 1.0, u_max_size), u_min_size);
  // Stochastic transparency, hashed from the point id: the same points in every frame and tile.
  if (u_opacity_draws != 0 && !(id_rand(point_ids[index], kOpacitySalt, 0u) < splat_opacity[index])) s.visible = false;
  return s;
}

vec4 point_color(uint index) {
  vec4 c = source_color(index);
  if (u_shading != 0) c = vec4(diffuse_shaded(vec3(c), view_normal(index), u_light_dir, u_shading_strength), c.a);
  return c;
}

// Coverage rule shared by both rasterizers: pixel centres within the disk
// of the splat; below 2 px, within its square (as GL point sprites do).
bool covers(vec2 offset, float diameter) {
  float r = 0.5 * diameter;
  if (diameter < 2.0) return abs(offset.x) <= r && abs(offset.y) <= r;
  return dot(offset, offset) <= r * r;
}
