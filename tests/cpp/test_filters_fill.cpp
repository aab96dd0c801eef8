// Hole filling: gaps inside a surface close with the surrounding colour;
// the outline and lone points do not grow.
#include <gtest/gtest.h>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

TEST(FilterFillHoles, ClosesGapsInsideASurfaceOnly) {
  Image in({96, 96});
  const glm::vec4 colour(0.3f, 0.6f, 0.9f, 1.0f);
  for (int y = 20; y < 76; ++y)
    for (int x = 20; x < 76; ++x)
      if (hash_noise(x, y, 9) > -0.4f) in.set(x, y, colour);  // 30 % missing
  in.set(5, 5, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));             // a lone point
  const FilterRun run = run_filter(in, "fill_holes");
  maybe_dump(run.out, "fill_holes");
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const glm::vec4 o = run.out.at(x, y);
      if (o == kSentinel) continue;
      // Holes on the region's outermost rows may be outside it: the border
      // of a sparse surface is only known to a pixel or two.
      const bool interior = x >= 23 && x < 73 && y >= 23 && y < 73;
      const bool outside = x < 19 || x >= 77 || y < 19 || y >= 77;
      if (interior) {
        ASSERT_EQ(o.a, 1.0f) << x << "," << y;
        for (int k = 0; k < 3; ++k) {
          ASSERT_NEAR(o[k], colour[k], 1e-5f) << x << "," << y;
        }
      }
      if (outside && !(x == 5 && y == 5)) {
        ASSERT_EQ(o.a, 0.0f) << "grew at " << x << "," << y;
      }
    }
  EXPECT_EQ(run.out.at(5, 5), in.at(5, 5)) << "the lone point stays as it is";
}

TEST(FilterFillHoles, KeepsCoveredPixelsAndFillsWithTheLocalMean) {
  Image in({64, 32});
  for (int y = 4; y < 28; ++y)
    for (int x = 4; x < 60; ++x)
      if ((x + y) % 2 == 0) in.set(x, y, x < 32 ? glm::vec4(1, 1, 1, 1) : glm::vec4(0, 0, 0, 1));  // checkerboard
  const FilterRun run = run_filter(in, "fill_holes");
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 56; ++x) {
      if (in.at(x, y).a > 0.0f) {
        ASSERT_EQ(run.out.at(x, y), in.at(x, y));
      } else if (x < 26 || x > 38) {  // farther than the kernel from the colour edge
        ASSERT_NEAR(run.out.at(x, y).g, x < 32 ? 1.0f : 0.0f, 1e-4f) << x << "," << y;
      }
    }
}

}  // namespace
