// Edge enhancement from depth: eye-dome lighting darkens surfaces just
// behind nearer ones, depth contours become lines, flat depth is untouched,
// silhouettes only around dense regions.
#include <gtest/gtest.h>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

// A far plane (depth 10) with a nearer square (depth 5) over its middle.
Image occlusion_image() {
  Image img({128, 96});
  img.depth.assign(size_t(128 * 96), std::numeric_limits<float>::infinity());
  for (int y = 8; y < 88; ++y)
    for (int x = 8; x < 120; ++x) {
      const bool near = x >= 44 && x < 84 && y >= 28 && y < 68;
      img.set(x, y, near ? glm::vec4(0.9f, 0.6f, 0.3f, 1.0f) : glm::vec4(0.5f, 0.7f, 0.9f, 1.0f));
      img.depth[img.index(x, y)] = near ? 5.0f : 10.0f;
    }
  return img;
}

TEST(FilterEdgeEnhance, EyeDomeLightingDarkensOnlyWhatLiesBehindAContour) {
  const Image in = occlusion_image();
  const FilterRun run = run_filter(in, "edge_enhance", {{"outline_width", {0}}});
  maybe_dump(run.out, "edl_occlusion");
  EXPECT_LT(run.out.at(43, 48).b, 0.5f * in.at(43, 48).b) << "far pixel next to the near square";
  EXPECT_EQ(run.out.at(44, 48), in.at(44, 48)) << "the near square's own border is not shaded";
  EXPECT_EQ(run.out.at(64, 48), in.at(64, 48)) << "flat depth: unchanged";
  EXPECT_EQ(run.out.at(20, 20), in.at(20, 20)) << "flat depth: unchanged";
}

TEST(FilterEdgeEnhance, DepthContoursBecomeLinesOfTheGivenWidth) {
  const Image in = occlusion_image();
  for (int width : {1, 3}) {
    const FilterRun run = run_filter(in, "edge_enhance",
                                     {{"edl_strength", {0}}, {"outline_width", {double(width)}},
                                      {"edge_color", {1, 1, 1, 1}}, {"silhouette", {0}}});
    int line = 0;
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 128; ++x) line += run.out.at(x, y) == glm::vec4(1.0f);
    // A ring of `width` pixels around the 40x40 square, on the far plane.
    const int expected = (40 + 2 * width) * (40 + 2 * width) - 40 * 40;
    EXPECT_NEAR(line, expected, expected * 0.15) << width;
    for (int dx = 1; dx <= width; ++dx) EXPECT_EQ(run.out.at(44 - dx, 48), glm::vec4(1.0f)) << width;
    EXPECT_NE(run.out.at(44 - width - 1, 48), glm::vec4(1.0f)) << width;
    EXPECT_EQ(run.out.at(44, 48), in.at(44, 48)) << "the occluder keeps its colour";
  }
}

TEST(FilterEdgeEnhance, SilhouettesOnlyAroundDenseRegions) {
  Image in = sparse_points({96, 96}, 6, {0.7f, 0.7f, 0.7f});
  for (int y = 22; y < 68; ++y)  // lone points keep 8 px away from the square
    for (int x = 22; x < 68; ++x) in.set(x, y, glm::vec4(0.0f));
  for (int y = 30; y < 60; ++y)
    for (int x = 30; x < 60; ++x) in.set(x, y, glm::vec4(0.7f, 0.7f, 0.7f, 1.0f));
  const FilterRun run = run_filter(in, "edge_enhance", {{"outline_width", {2}}});
  maybe_dump(run.out, "edl_silhouette");
  int ring = 0, stray = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const glm::vec4 o = run.out.at(x, y);
      if (o == kSentinel || in.at(x, y).a > 0.0f || o.a == 0.0f) continue;
      const bool near_square = x >= 28 && x < 62 && y >= 28 && y < 62;
      (near_square ? ring : stray)++;
    }
  // A 2 px ring (34 * 34 - 30 * 30 = 256 px) with rounded corners.
  EXPECT_GE(ring, 210);
  EXPECT_LE(ring, 256);
  EXPECT_EQ(stray, 0) << "no rings around lone points";
}

}  // namespace
