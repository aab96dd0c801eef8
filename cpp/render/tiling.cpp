#include "render/tiling.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pointnpr {

TilePlan whole_frame(glm::ivec2 frame) {
  TilePlan plan;
  plan.region_size = frame;
  plan.interior = frame;
  plan.tiles.push_back({Rect{{0, 0}, frame}, Rect{{0, 0}, frame}});
  return plan;
}

TilePlan plan_tiles(glm::ivec2 frame, int halo, size_t budget_bytes, int tile_size, int max_image_size) {
  if (frame.x <= 0 || frame.y <= 0) throw ParameterError("plan_tiles: empty frame");
  if (halo < 0 || tile_size < 0) throw ParameterError("plan_tiles: negative halo or tile size");
  const double frame_bytes = double(frame.x) * double(frame.y) * double(kBytesPerTilePixel);
  const bool fits_whole = frame_bytes <= double(budget_bytes) && frame.x <= max_image_size && frame.y <= max_image_size;
  if (tile_size == 0 && fits_whole) return whole_frame(frame);
  if (tile_size >= std::max(frame.x, frame.y) && frame.x <= max_image_size && frame.y <= max_image_size)
    return whole_frame(frame);

  TilePlan plan;
  plan.halo = halo;
  int side = tile_size;
  const bool from_budget = side == 0;
  if (from_budget) {
    const double region = std::floor(std::sqrt(double(budget_bytes) / double(kBytesPerTilePixel)));
    side = int(std::min(region, double(max_image_size))) - 2 * halo;
    side = side / 16 * 16;
  }
  side = std::min(side, max_image_size - 2 * halo);
  if (side < kTileAlign) {
    // The halo alone nearly fills the budget (or the GL limit): the smallest
    // tile, over the budget, rather than a frame that cannot be drawn.
    side = kTileAlign;
    plan.fits_budget = false;
  }
  if (side + 2 * halo > max_image_size)
    throw GLError("a tile of " + std::to_string(side) + " pixels and its halo of " + std::to_string(halo) +
                  " exceed the GL image limit of " + std::to_string(max_image_size) + " pixels per side");
  glm::ivec2 interior(side);
  if (from_budget) {
    // As many columns and rows as the largest tile needs, each as small as
    // they allow: 3840x2160 in tiles of 1280 becomes 3 x 2 tiles of 1280x1088.
    const glm::ivec2 count = (frame + side - 1) / side;
    interior = glm::min((((frame + count - 1) / count) + 15) / 16 * 16, glm::ivec2(side));
  }
  plan.interior = interior;
  plan.region_size = glm::min(interior + 2 * halo, frame);
  if (double(plan.region_size.x) * double(plan.region_size.y) * double(kBytesPerTilePixel) > double(budget_bytes))
    plan.fits_budget = false;
  for (int y = 0; y < frame.y; y += interior.y)
    for (int x = 0; x < frame.x; x += interior.x) {
      Tile t;
      t.interior = Rect{{x, y}, glm::min(glm::ivec2(x, y) + interior, frame)};
      // Halo on both sides, slid inside the frame where it meets the border:
      // one image size for every tile, and the frame's edges are the images'.
      t.region.min = glm::clamp(t.interior.min - halo, glm::ivec2(0), frame - plan.region_size);
      t.region.max = t.region.min + plan.region_size;
      plan.tiles.push_back(t);
    }
  return plan;
}

}  // namespace pointnpr
