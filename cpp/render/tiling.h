#pragma once
// Large frames in tiles (issue 17): the frame is cut into tiles whose GL
// images fit a memory budget; each tile draws its interior grown by a halo
// (every segment's mark reach, filter footprints and inpainting radius), so
// the pixels it delivers saw everything they depend on, and the assembled
// frame is the same bytes as the frame drawn whole. Shaders place what
// depends on the pixel (projection, noise, patterns) by the frame pixel:
// local + the tile's origin (MarkTargets::origin, pixel_origin()).
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "render/filter.h"  // Rect

namespace pointnpr {

// GL memory a frame pixel costs (frame targets, filter and mark scratch);
// the issue measured ~120 B for plain points and ~220 B with a cartoon
// (the gap fill's per-pixel spacing and depths add 8 B since, its cells
// of 2 to 16 px about 24 B: filter_chain.cpp, rounded up).
constexpr size_t kBytesPerTilePixel = 288;
constexpr size_t kDefaultMemoryBudget = size_t(2) << 30;  // 2 GiB
// Tiles' interiors are at least this per side (and multiples of 16, the
// compute passes' work group side).
constexpr int kTileAlign = 64;

struct Tile {
  Rect interior;  // frame pixels this tile delivers
  Rect region;    // frame pixels it draws: the interior and its halo, inside the frame
};

struct TilePlan {
  glm::ivec2 region_size{0, 0};  // every tile's region: the GL images' size
  int halo = 0;
  glm::ivec2 interior{0, 0};     // interior size (the last row and column may be smaller)
  std::vector<Tile> tiles;       // row by row, bottom first
  bool fits_budget = true;       // false when even the smallest tile is over the budget
};

// Tiles for a frame. `tile_size` > 0 asks for interiors of that side (tests,
// benchmarks); else the interior is the largest whose region fits
// `budget_bytes`, evened out over the rows and columns it needs (less halo
// drawn twice), and a frame that fits whole is one tile. Regions never
// exceed `max_image_size` per side. Every region has the same size and its
// frame edges are the images' edges (filters see the frame's border).
TilePlan plan_tiles(glm::ivec2 frame, int halo, size_t budget_bytes, int tile_size, int max_image_size);

// One tile covering the frame (marks that cannot draw tiles).
TilePlan whole_frame(glm::ivec2 frame);

}  // namespace pointnpr
