// Oil paint (anisotropic Kuwahara): a step edge stays sharp while noise
// variance drops; the coverage-normalized blur, by contrast, smears it.
#include <gtest/gtest.h>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

// Width in pixels of the 10 %-90 % rise of the mean row profile across the
// vertical step at x = size.x / 2.
int edge_width(const Image& img, float lo, float hi, int y0, int y1) {
  int first = -1, last = -1;
  for (int x = 0; x < img.size.x; ++x) {
    double v = 0;
    for (int y = y0; y < y1; ++y) v += img.at(x, y).g;
    v /= (y1 - y0);
    const double t = (v - lo) / (hi - lo);
    if (x > 16 && x < img.size.x - 16) {
      if (t > 0.1 && first < 0) first = x;
      if (t < 0.9) last = x;
    }
  }
  return last - first + 1;
}

TEST(FilterKuwahara, KeepsAStepEdgeSharpAndReducesNoiseVariance) {
  const glm::ivec2 size(160, 96);
  const float lo = 0.25f, hi = 0.75f;
  const Image in = step_image(size, glm::vec3(lo), glm::vec3(hi), 0.1f);
  const FilterRun run = run_filter(in, "kuwahara", {{"radius", {5}}, {"impasto", {0}}});
  maybe_dump(run.out, "kuwahara_step");
  // Flat patches away from the step and the segment's border.
  const double before = patch_variance(in, 24, 24, 64, 72) + patch_variance(in, 96, 24, 136, 72);
  const double after = patch_variance(run.out, 24, 24, 64, 72) + patch_variance(run.out, 96, 24, 136, 72);
  EXPECT_LT(after, before / 8.0) << "noise variance drops at least 8x";
  EXPECT_LE(edge_width(run.out, lo, hi, 24, 72), 2) << "the step stays within 2 px";
  const FilterRun blurred = run_filter(in, "blur", {{"sigma", {3}}});
  EXPECT_GE(edge_width(blurred.out, lo, hi, 24, 72), 5) << "a blur of similar smoothing smears it";
  // Means of the flat regions are kept.
  EXPECT_NEAR(run.out.at(40, 48).g, lo, 0.05f);
  EXPECT_NEAR(run.out.at(120, 48).g, hi, 0.05f);
}

TEST(FilterKuwahara, ImpastoStreaksFollowTheImageStructure) {
  // Horizontal bands: edges run along x, so the bristle streaks do too and
  // the relief shading changes much more across them (along y).
  Image in({128, 128});
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) in.set(x, y, glm::vec4(glm::vec3((y / 12) % 2 ? 0.7f : 0.4f), 1.0f));
  const FilterRun flat = run_filter(in, "kuwahara", {{"impasto", {0}}});
  const FilterRun paint = run_filter(in, "kuwahara", {{"impasto", {2}}});
  maybe_dump(paint.out, "kuwahara_impasto");
  double along = 0, across = 0, relief = 0;
  auto shade = [&](int x, int y) { return paint.out.at(x, y).g - flat.out.at(x, y).g; };
  for (int y = 16; y < 112; ++y)
    for (int x = 16; x < 112; ++x) {
      along += std::abs(shade(x + 1, y) - shade(x, y));
      across += std::abs(shade(x, y + 1) - shade(x, y));
      relief += std::abs(shade(x, y));
    }
  EXPECT_GT(relief / (96 * 96), 0.01) << "the paint has visible relief";
  EXPECT_GT(across, 2.0 * along) << "streaks run along the bands";
}

TEST(FilterKuwahara, BackgroundDoesNotBleedIntoTheSegment) {
  const Image in = disk_image({96, 96}, {48, 48}, 28, {0.9f, 0.8f, 0.1f}, 0.05f);
  const FilterRun run = run_filter(in, "kuwahara", {{"impasto", {0}}});
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const glm::vec4 o = run.out.at(x, y);
      if (in.at(x, y).a > 0.0f) {
        ASSERT_GT(o.r, 0.8f) << x << "," << y;
        ASSERT_EQ(o.a, 1.0f);
      } else {
        ASSERT_TRUE(o == glm::vec4(0.0f) || o == kSentinel) << x << "," << y;
      }
    }
}

}  // namespace
