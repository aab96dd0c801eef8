// Cartoon: the CIELAB bilateral smoothing before banding keeps a step edge
// sharp while reducing noise variance.
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

}  // namespace
