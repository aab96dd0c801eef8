#pragma once
// The gaussians mark: a splat capture's 3D Gaussians drawn as the 3DGS
// reference rasterizer draws them (marks/gaussians/native.cpp).
#include <vector>

#include <glm/glm.hpp>

#include "render/mark.h"

namespace pointnpr::gaussians {

struct DrawSettings {
  int sh_degree = 3;          // at most the cloud's
  float max_radius = 512.0f;  // px
  float depth_alpha = 0.5f;   // a pixel's depth: where its opacity first reaches this
  float min_coverage = 0.0f;  // pixels less opaque than this are left empty
  // Floaters: splats dropped before drawing (0: that test off).
  float min_opacity = 0.0f;
  float max_scale = 0.0f;     // scene units, the largest axis
  float isolation = 0.0f;     // x the cloud's median spacing (mean distance to 8 neighbours)
  // Not empty: chunk c draws the first queue_counts[c] splats of its queue order.
  std::vector<uint32_t> queue_counts;
  bool gl = false;  // composite by GL's compute pass (gl.cpp) instead of on the CPU's threads
};

// A splat as the GL pass reads it (std430, shaders/gaussians.comp).
struct GpuRecord {
  glm::vec4 center_depth_opacity{0.0f};  // centre x, y (the images' pixels + 0.5 convention), view depth, opacity
  glm::vec4 conic{0.0f};
  glm::vec4 color{0.0f};
  glm::ivec4 box{0, 0, -1, -1};  // pixels it reaches, relative to the clip's corner: x0, y0, x1, y1
};
static_assert(sizeof(GpuRecord) == 64, "std430 layout of shaders/gaussians.comp's Record");

// The per-pixel compositing on GL (marks/gaussians/gl.cpp): the tiles'
// sorted lists (tile t: lists[start[t], start[t + 1])) of `records`, 16 x 16
// pixels a workgroup, into the targets' colour and depth over ctx.clip.
void composite_gl(const MarkContext& ctx, const DrawSettings& s, const std::vector<GpuRecord>& records,
                  const std::vector<uint32_t>& start, const std::vector<uint32_t>& lists, int tiles_x, int tiles_y);

// Counts of what a frame drew and dropped, for stats and tests.
struct DrawCounts {
  size_t drawn = 0, culled = 0, floaters = 0, plain_points = 0;
};

// The TBB rasterizer: preprocess every splat, bin into 16 px tiles, sort
// each tile's splats by (depth, point key), composite front to back.
DrawCounts draw_native(const MarkContext& ctx, const DrawSettings& s);

}  // namespace pointnpr::gaussians
