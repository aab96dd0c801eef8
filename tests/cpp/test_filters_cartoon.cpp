// Cartoon: the CIELAB bilateral smoothing before banding keeps a step edge
// sharp while reducing noise variance.
#include <cmath>

#include <gtest/gtest.h>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

// Mean green across rows [y0, y1) at column x.
double column_mean(const Image& img, int x, int y0, int y1) {
  double s = 0;
  for (int y = y0; y < y1; ++y) s += img.at(x, y).g;
  return s / (y1 - y0);
}

TEST(FilterCartoon, BilateralSmoothingKeepsTheStepAndRemovesNoise) {
  const Image in = step_image({160, 96}, glm::vec3(0.3f), glm::vec3(0.7f), 0.06f);
  // Many soft bands and no edges: the output shows the smoothed image.
  const std::map<std::string, std::vector<double>> base = {
      {"levels", {32}}, {"quantize_sharpness", {0}}, {"edge_strength", {0}}, {"outline_width", {0}}};
  auto with = [&](int iterations) {
    auto params = base;
    params["smoothing"] = {double(iterations)};
    return run_filter(in, "cartoon", params).out;
  };
  const Image raw = with(0), smooth = with(3);
  maybe_dump(smooth, "cartoon_bilateral");
  const double before = patch_variance(raw, 24, 24, 64, 72) + patch_variance(raw, 96, 24, 136, 72);
  const double after = patch_variance(smooth, 24, 24, 64, 72) + patch_variance(smooth, 96, 24, 136, 72);
  EXPECT_LT(after, before / 4.0) << "noise variance drops at least 4x";
  // The step between x = 79 and 80 stays a one-pixel step.
  const double lo = column_mean(smooth, 74, 24, 72), hi = column_mean(smooth, 85, 24, 72);
  EXPECT_NEAR(column_mean(smooth, 79, 24, 72), lo, 0.1 * (hi - lo));
  EXPECT_NEAR(column_mean(smooth, 80, 24, 72), hi, 0.1 * (hi - lo));
}

// quantize_sharpness runs from smooth to hard as documented: on a grey ramp
// with nothing else on, 0 is the input itself, and the distance from the
// input (how flat the bands are) grows with every step up the range.
TEST(FilterCartoon, BandHardnessGrowsWithSharpnessFromTheIdentity) {
  Image in({256, 8});
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 256; ++x) in.set(x, y, glm::vec4(glm::vec3((x + 0.5f) / 256.0f), 1.0f));
  auto distance_from_input = [&](double sharpness) {
    const Image out = run_filter(in, "cartoon", {{"levels", {5}}, {"quantize_sharpness", {sharpness}}, {"smoothing", {0}},
                                                 {"edge_strength", {0}}, {"outline_width", {0}}, {"fill_gaps", {0}}})
                          .out;
    double sum = 0.0;
    for (int x = 0; x < 256; ++x) sum += std::abs(out.at(x, 4).g - in.at(x, 4).g);
    return sum / 256.0;
  };
  double previous = distance_from_input(0.0);
  EXPECT_LT(previous, 2e-3) << "sharpness 0 draws no bands";
  for (double sharpness : {1.0, 2.0, 4.0, 8.0, 16.0, 50.0}) {
    const double d = distance_from_input(sharpness);
    EXPECT_GT(d, previous + 1e-3) << "sharpness " << sharpness;
    previous = d;
  }
  // Hard at the top: within 2 % of a step of rounding to the nearest level
  // (a band of 1/4 spans 0.25 / 2 = 0.125 mean distance).
  EXPECT_NEAR(previous, 0.0625, 0.02 * 0.25);
}

}  // namespace
