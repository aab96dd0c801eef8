// Tile plans (render/tiling.h): interiors partition the frame, regions hold
// their interior and its halo inside the frame, all of one size.
#include <gtest/gtest.h>

#include <vector>

#include "render/tiling.h"

namespace pointnpr {
namespace {

void expect_valid(const TilePlan& plan, glm::ivec2 frame) {
  std::vector<int> owner(size_t(frame.x) * size_t(frame.y), 0);
  for (const Tile& t : plan.tiles) {
    EXPECT_EQ(t.region.size(), plan.region_size);
    EXPECT_GE(t.region.min.x, 0);
    EXPECT_GE(t.region.min.y, 0);
    EXPECT_LE(t.region.max.x, frame.x);
    EXPECT_LE(t.region.max.y, frame.y);
    // The halo around the interior lies in the region wherever the frame has pixels.
    EXPECT_LE(t.region.min.x, std::max(t.interior.min.x - plan.halo, 0));
    EXPECT_LE(t.region.min.y, std::max(t.interior.min.y - plan.halo, 0));
    EXPECT_GE(t.region.max.x, std::min(t.interior.max.x + plan.halo, frame.x));
    EXPECT_GE(t.region.max.y, std::min(t.interior.max.y + plan.halo, frame.y));
    for (int y = t.interior.min.y; y < t.interior.max.y; ++y)
      for (int x = t.interior.min.x; x < t.interior.max.x; ++x) ++owner[size_t(y) * size_t(frame.x) + size_t(x)];
  }
  for (int n : owner) ASSERT_EQ(n, 1);  // every pixel delivered by exactly one tile
}

TEST(Tiling, AFrameWithinTheBudgetIsOneTile) {
  const TilePlan plan = plan_tiles({1920, 1080}, 40, kDefaultMemoryBudget, 0, 16384);
  ASSERT_EQ(plan.tiles.size(), 1u);
  EXPECT_EQ(plan.region_size, glm::ivec2(1920, 1080));
  expect_valid(plan, {1920, 1080});
}

TEST(Tiling, TilesOfAGivenSizeCoverAFrameTheyDoNotDivide) {
  const glm::ivec2 frame{333, 257};
  const TilePlan plan = plan_tiles(frame, 27, kDefaultMemoryBudget, 64, 16384);
  EXPECT_EQ(plan.tiles.size(), 6u * 5u);
  EXPECT_EQ(plan.region_size, glm::ivec2(64 + 2 * 27));
  expect_valid(plan, frame);
}

TEST(Tiling, TheBudgetBoundsEveryTilesImages) {
  const glm::ivec2 frame{16384, 16384};
  const size_t budget = size_t(1) << 30;
  const TilePlan plan = plan_tiles(frame, 100, budget, 0, 16384);
  EXPECT_TRUE(plan.fits_budget);
  EXPECT_GT(plan.tiles.size(), 1u);
  EXPECT_LE(size_t(plan.region_size.x) * size_t(plan.region_size.y) * kBytesPerTilePixel, budget);
  EXPECT_EQ(plan.interior.x % 16, 0);
  EXPECT_EQ(plan.interior.y % 16, 0);
  expect_valid(plan, frame);
}

TEST(Tiling, TilesFromTheBudgetAreEvenedOutOverTheFrame) {
  // 3840x2160 with regions of at most 1448 px (576 MiB at kBytesPerTilePixel
  // 288): 3 x 2 tiles, the rows as tall as they need to be rather than one
  // full row and a sliver.
  const TilePlan plan = plan_tiles({3840, 2160}, 60, size_t(576) << 20, 0, 16384);
  ASSERT_EQ(plan.tiles.size(), 6u);
  EXPECT_EQ(plan.interior, glm::ivec2(1280, 1088));
  EXPECT_EQ(plan.region_size, glm::ivec2(1400, 1208));
  expect_valid(plan, {3840, 2160});
}

TEST(Tiling, FramesBeyondTheGlLimitAreTiled) {
  const glm::ivec2 frame{32768, 600};
  const TilePlan plan = plan_tiles(frame, 10, size_t(64) << 30, 0, 16384);
  EXPECT_GT(plan.tiles.size(), 1u);
  EXPECT_LE(plan.region_size.x, 16384);
  expect_valid(plan, frame);
}

TEST(Tiling, AHaloOverTheBudgetStillGivesTilesAndSaysSo) {
  const TilePlan plan = plan_tiles({4000, 3000}, 300, size_t(1) << 20, 0, 16384);
  EXPECT_FALSE(plan.fits_budget);
  EXPECT_EQ(plan.interior, glm::ivec2(kTileAlign));
  expect_valid(plan, {4000, 3000});
}

}  // namespace
}  // namespace pointnpr
