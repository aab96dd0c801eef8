#pragma once
// The gaussians mark: a splat capture's 3D Gaussians drawn as the 3DGS
// reference rasterizer draws them (marks/gaussians/native.cpp).
#include <vector>

#include "render/mark.h"

namespace pointnpr::gaussians {

struct DrawSettings {
  int sh_degree = 3;          // at most the cloud's
  float max_radius = 512.0f;  // px
  float depth_alpha = 0.5f;   // a pixel's depth: where its opacity first reaches this
  // Floaters: splats dropped before drawing (0: that test off).
  float min_opacity = 0.0f;
  float max_scale = 0.0f;     // scene units, the largest axis
  float isolation = 0.0f;     // x the cloud's median spacing (mean distance to 8 neighbours)
  // Not empty: chunk c draws the first queue_counts[c] splats of its queue order.
  std::vector<uint32_t> queue_counts;
};

// Counts of what a frame drew and dropped, for stats and tests.
struct DrawCounts {
  size_t drawn = 0, culled = 0, floaters = 0, plain_points = 0;
};

// The TBB rasterizer: preprocess every splat, bin into 16 px tiles, sort
// each tile's splats by (depth, point key), composite front to back.
DrawCounts draw_native(const MarkContext& ctx, const DrawSettings& s);

}  // namespace pointnpr::gaussians
