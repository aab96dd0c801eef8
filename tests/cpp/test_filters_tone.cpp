// Posterize, colour grading and Gaussian blur: the property each exists for.
#include <gtest/gtest.h>

#include <set>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

struct Stats {
  glm::dvec3 mean{0.0};
  double variance = 0.0;  // mean over channels
  int n = 0;
};

// Mean and variance of `img` over the pixels `mask` covers in [x0,x1)x[y0,y1).
Stats stats(const Image& img, const Image& mask, int x0, int y0, int x1, int y1) {
  Stats s;
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const glm::vec4 c = img.at(x, y);
      if (mask.at(x, y).a <= 0.0f) continue;
      sum += glm::dvec3(c);
      sum2 += glm::dvec3(c) * glm::dvec3(c);
      ++s.n;
    }
  if (s.n == 0) return s;
  s.mean = sum / double(s.n);
  const glm::dvec3 var = sum2 / double(s.n) - s.mean * s.mean;
  s.variance = (var.x + var.y + var.z) / 3.0;
  return s;
}

TEST(FilterPosterize, YieldsAtMostLevelsPerChannel) {
  const Image in = gradient_image({160, 120});
  for (int levels : {2, 3, 5}) {
    const FilterRun run = run_filter(in, "posterize", {{"levels", {double(levels)}}, {"space", {0}}, {"smoothness", {0}}});
    std::set<float> values[3];
    for (int y = 0; y < in.size.y; ++y)
      for (int x = 0; x < in.size.x; ++x) {
        const glm::vec4 c = run.out.at(x, y);
        if (in.at(x, y).a <= 0.0f) {
          ASSERT_TRUE(c == glm::vec4(0.0f) || c == kSentinel) << "background must stay untouched";
          continue;
        }
        for (int k = 0; k < 3; ++k) values[k].insert(c[k]);
      }
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(int(values[k].size()), levels) << "channel " << k;
      EXPECT_GE(int(values[k].size()), 2) << "channel " << k;
    }
  }
}

TEST(FilterPosterize, LightnessModeKeepsGreysGreyWithAtMostLevelsTones) {
  Image in({128, 16});
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 128; ++x) in.set(x, y, glm::vec4(glm::vec3(float(x) / 127.0f), 1.0f));
  const FilterRun run = run_filter(in, "posterize", {{"levels", {4}}, {"space", {1}}, {"smoothness", {0}}});
  std::set<int> tones;
  for (int x = 0; x < 128; ++x) {
    const glm::vec4 c = run.out.at(x, 5);
    EXPECT_NEAR(c.r, c.g, 1e-4f);
    EXPECT_NEAR(c.g, c.b, 1e-4f);
    tones.insert(int(std::lround(c.r * 1000.0f)));
  }
  EXPECT_EQ(tones.size(), 4u);
}

TEST(FilterPosterize, OklabModeYieldsFewColours) {
  const Image in = gradient_image({96, 72});
  const FilterRun run = run_filter(in, "posterize", {{"levels", {3}}, {"space", {2}}, {"smoothness", {0}}});
  std::set<std::tuple<int, int, int>> colours;
  for (int y = 0; y < in.size.y; ++y)
    for (int x = 0; x < in.size.x; ++x)
      if (in.at(x, y).a > 0.0f) {
        const glm::vec4 c = run.out.at(x, y) * 4096.0f;
        colours.insert({int(std::lround(c.r)), int(std::lround(c.g)), int(std::lround(c.b))});
      }
  EXPECT_LE(colours.size(), 27u);  // 3 levels on each of L, a, b
  EXPECT_GE(colours.size(), 3u);
}

TEST(FilterColorGrade, DefaultsAreTheIdentity) {
  const Image in = gradient_image({64, 48});
  const FilterRun run = run_filter(in, "color_grade");
  int compared = 0;
  for (int y = 0; y < in.size.y; ++y)
    for (int x = 0; x < in.size.x; ++x) {
      if (in.at(x, y).a <= 0.0f) continue;
      for (int k = 0; k < 4; ++k) ASSERT_NEAR(run.out.at(x, y)[k], in.at(x, y)[k], 2e-4f) << x << "," << y;
      ++compared;
    }
  EXPECT_GT(compared, 1000);
}

TEST(FilterColorGrade, ExposureSaturationAndHue) {
  Image in({32, 32});
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) in.set(x, y, glm::vec4(0.8f, 0.3f, 0.2f, 1.0f));
  auto lin = [](float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); };
  const glm::vec4 brighter = run_filter(in, "color_grade", {{"exposure", {1}}}).out.at(10, 10);
  EXPECT_NEAR(lin(brighter.g), 2.0f * lin(0.3f), 2e-3f);
  EXPECT_NEAR(lin(brighter.b), 2.0f * lin(0.2f), 2e-3f);
  const glm::vec4 grey = run_filter(in, "color_grade", {{"saturation", {0}}}).out.at(10, 10);
  EXPECT_NEAR(grey.r, grey.g, 2e-3f);
  EXPECT_NEAR(grey.g, grey.b, 2e-3f);
  const glm::vec4 turned = run_filter(in, "color_grade", {{"hue_shift", {180}}}).out.at(10, 10);
  EXPECT_LT(turned.r, turned.g);  // orange-red turns towards cyan-blue
  EXPECT_LT(turned.r, turned.b);
  const glm::vec4 full = run_filter(in, "color_grade", {{"hue_shift", {180}}, {"saturation", {1}}}).out.at(3, 3);
  EXPECT_EQ(full, turned);
}

TEST(FilterBlur, PreservesMeanColourAndReducesNoiseVariance) {
  const Image in = disk_image({160, 120}, {80, 60}, 50, {0.5f, 0.4f, 0.6f}, 0.3f);
  const FilterRun run = run_filter(in, "blur", {{"sigma", {2.0}}});
  const Stats before = stats(in, in, 0, 0, 160, 120), after = stats(run.out, in, 0, 0, 160, 120);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(after.mean[k], before.mean[k], 2e-3) << k;
  // White noise through a 2D Gaussian of sigma 2: variance / (4 pi sigma^2) = / 50.
  EXPECT_LT(after.variance, before.variance / 20.0);
}

TEST(FilterBlur, BackgroundDoesNotBleedIn) {
  const Image in = disk_image({96, 96}, {48, 48}, 30, {1.0f, 0.0f, 0.0f});
  const FilterRun run = run_filter(in, "blur", {{"sigma", {4.0}}});
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const glm::vec4 c = run.out.at(x, y);
      if (in.at(x, y).a > 0.0f) {
        ASSERT_NEAR(c.r, 1.0f, 1e-5f);
        ASSERT_NEAR(c.g, 0.0f, 1e-5f);
        ASSERT_EQ(c.a, 1.0f);
      } else {
        ASSERT_TRUE(c == glm::vec4(0.0f) || c == kSentinel) << x << "," << y;
      }
    }
}

}  // namespace
