#pragma once
// Round splats (the `points` mark), also used by other marks for their
// depth passes: discs at each point, nearest wins, ties broken by point key.
#include "render/mark.h"

namespace pointnpr {

struct SplatSettings {
  bool world_size = false;     // diameter in scene units (else pixels)
  // world_size: each point's SplatRadius (k = splat_k; a Gaussian splat's footprint, a plain point's
  // spacing) instead of world_diameter.
  bool splat_size = false;
  int splat_k = 8;
  // splat_size: the diameter in SplatRadius (2: a Gaussian splat's
  // footprint; 1: size_mode spacing, the point's mean distance to its
  // neighbours), and at least this many pixels (size_mode spacing:
  // point_size).
  float radius_diameters = 2.0f;
  float min_pixels = 0.0f;
  // A Gaussian splat's opacity is the chance it is drawn (SplatOpacity, PointId).
  bool opacity_draws = false;
  float point_size = 2.0f;     // pixels
  float world_diameter = 0.05f;
  ColorSource color_source = ColorSource::Constant;
  glm::vec4 constant_color{0.8f, 0.8f, 0.8f, 1.0f};
  bool shading = false;
  float shading_strength = 0.0f;
  glm::vec3 light_dir{0.0f, 0.0f, 1.0f};  // towards the light, view space
  int normal_k = 16;           // normals read when shading
  // Continuous resolution queue (render/mark.h): when not empty, chunk c
  // draws only the first queue_counts[c] points of its queue order.
  std::vector<uint32_t> queue_counts;
  // draw_splats_native only: the linear depth over ctx.clip (row-major,
  // +inf where no disc) into this vector instead of the targets: a depth
  // pass another native mark tests against on the host.
  std::vector<float>* depth_only = nullptr;
};

// Largest splat on screen, in pixels (world sizes are capped to it).
constexpr float kMaxSplatPixels = 32.0f;

// Compute rasterizer (visibility by atomics, deterministic ties).
void draw_splats_compute(const MarkContext& ctx, const SplatSettings& s);
// The compute rasterizer's rules on the CPU's threads (marks/points/native.cpp):
// the same colour, depth and coverage from the host's copy of the points,
// uploaded into targets.color / targets.depth over ctx.clip.
void draw_splats_native(const MarkContext& ctx, const SplatSettings& s);
// A chunk's colour attribute on the host, as point_attributes.glsl's
// source_color() reads it (the native paths; shaders/point_color.glsl).
struct HostColors {
  ColorSource source = ColorSource::Constant;  // resolved (never Auto)
  const uint32_t* colors = nullptr;            // the cloud's arrays, cloud order
  const float* intensity = nullptr;
  const uint32_t* classification = nullptr;
  float intensity_scale = 1.0f;
  glm::vec4 constant{0.8f, 0.8f, 0.8f, 1.0f};
  glm::vec4 at(uint32_t index) const;  // alpha 1
};
HostColors host_colors(const GpuCloud& gpu, const PointCloud& cloud, ColorSource source, glm::vec4 constant);
// The median luminance (display values) of the cloud's colours under
// `colors`' source, from at most 65,536 points evenly spread through it
// (computed once per cloud and source, kept in the cloud's host slots); 0
// for the constant source.
float median_luminance(const GpuCloud& gpu, const PointCloud& cloud, const HostColors& colors);
// GL_POINTS with reversed-Z depth into targets.gl_depth; also writes colour
// and linear depth to targets.color / targets.depth.
void draw_splats_gl(const MarkContext& ctx, const SplatSettings& s);

}  // namespace pointnpr
