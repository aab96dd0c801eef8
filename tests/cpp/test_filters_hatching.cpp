// Pencil hatching: ink grows with tone, strokes run along the given angle.
#include <gtest/gtest.h>

#include "filter_images.h"
#include "render/renderer.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

Image grey(glm::ivec2 size, float v) {
  Image img(size);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) img.set(x, y, glm::vec4(v, v, v, 1.0f));
  return img;
}

// Mean darkness relative to the paper (0 = paper, 1 = pencil) in the middle.
double ink(const Image& out) {
  double s = 0;
  int n = 0;
  for (int y = 8; y < out.size.y - 8; ++y)
    for (int x = 8; x < out.size.x - 8; ++x) s += (0.97 - out.at(x, y).r) / (0.97 - 0.12), ++n;
  return s / n;
}

TEST(FilterHatching, InkGrowsWithTone) {
  double previous = -1.0;
  for (float v : {1.0f, 0.8f, 0.6f, 0.4f, 0.2f, 0.05f}) {
    const FilterRun run = run_filter(grey({96, 96}, v), "pencil_hatching");
    if (v == 0.6f) maybe_dump(run.out, "hatching_grey60");
    const double amount = ink(run.out);
    EXPECT_GT(amount, previous + 0.02) << "grey " << v;
    if (v == 1.0f) {
      EXPECT_LT(amount, 0.02) << "white paper stays white";
    }
    previous = amount;
  }
  EXPECT_GT(previous, 0.3) << "black gets dense cross-hatching";
}

TEST(FilterHatching, StrokesRunAlongTheAngle) {
  const Image in = grey({96, 96}, 0.5f);
  for (double angle : {0.0, 90.0}) {
    const FilterRun run = run_filter(in, "pencil_hatching", {{"layers", {1}}, {"angle", {angle}}, {"grain", {0}}});
    double dx = 0, dy = 0;
    for (int y = 8; y < 88; ++y)
      for (int x = 8; x < 88; ++x) {
        dx += std::abs(run.out.at(x + 1, y).r - run.out.at(x, y).r);
        dy += std::abs(run.out.at(x, y + 1).r - run.out.at(x, y).r);
      }
    if (angle == 0.0) {
      EXPECT_LT(dx * 3, dy) << "horizontal strokes change little along x";
    } else {
      EXPECT_LT(dy * 3, dx) << "vertical strokes change little along y";
    }
  }
}

TEST(FilterHatching, OwnColourCanTintThePaper) {
  Image in({48, 48});
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) in.set(x, y, glm::vec4(0.9f, 0.5f, 0.5f, 1.0f));
  const glm::vec4 plain = run_filter(in, "pencil_hatching", {{"layers", {1}}}).out.at(24, 24);
  const FilterRun tinted = run_filter(in, "pencil_hatching", {{"color_mix", {1}}});
  int reddish = 0;
  for (int y = 8; y < 40; ++y)
    for (int x = 8; x < 40; ++x) reddish += tinted.out.at(x, y).r > tinted.out.at(x, y).g + 0.1f;
  EXPECT_GT(reddish, 32 * 32 / 2);
  EXPECT_NEAR(plain.r - plain.g, 0.01f, 0.05f) << "untinted paper is neutral";
}

// Mean |a(x + shift, y) - b(x, y)| over the grey channel in the middle.
double shifted_difference(const RenderResult& a, const RenderResult& b, glm::ivec2 size, int shift) {
  double sum = 0;
  int n = 0;
  for (int y = 30; y < size.y - 30; ++y)
    for (int x = 30; x < size.x - 30; ++x) {
      sum += std::abs(a.color[4 * (size_t(y) * size.x + size_t(x + shift))] - b.color[4 * (size_t(y) * size.x + size_t(x))]);
      ++n;
    }
  return sum / n;
}

TEST(FilterHatching, SurfaceStrokesMoveWithTheScanScreenStrokesDoNot) {
  // Pan the camera by exactly 4 pixels over a grey plane: surface strokes
  // move with it, screen strokes stay where they were.
  const glm::ivec2 size(200, 150);
  const Camera first = front_camera({0, 0, 10}, size);
  const double pan = 4.0 / first.pixels_per_unit(10.0, size.y);
  const Camera second = front_camera({pan, 0, 10}, size);
  Renderer renderer;
  for (const char* space : {"surface", "screen"}) {
    const double space_index = std::string(space) == "surface" ? 0 : 1;
    Scene scene;
    scene.segments.push_back(segment("plane", plane_cloud(-6, 6, -5, 5, 0, 0.02, {110, 110, 110}),
                                     style_with({{"point_size", {2}}},
                                                {{"pencil_hatching", {{"space", {space_index}}, {"grain", {0}}}}})));
    const RenderResult a = renderer.render(scene, first, settings(size));
    const RenderResult b = renderer.render(scene, second, settings(size));
    const double followed = shifted_difference(a, b, size, 4), stayed = shifted_difference(a, b, size, 0);
    if (std::string(space) == "surface") {
      EXPECT_LT(followed * 4, stayed) << "surface strokes follow the pan: " << followed << " vs " << stayed;
    } else {
      EXPECT_LT(stayed * 4, followed) << "screen strokes stay: " << stayed << " vs " << followed;
    }
  }
}

TEST(FilterHatching, SurfaceStrokeDensityOnScreenHoldsAcrossDistances) {
  // Twice as far, the planes halve their spacing level: about as much ink.
  const glm::ivec2 size(160, 120);
  Renderer renderer;
  Scene scene;
  scene.segments.push_back(segment("plane", plane_cloud(-30, 30, -25, 25, 0, 0.04, {110, 110, 110}),
                                   style_with({{"point_size", {2}}}, {{"pencil_hatching", {{"grain", {0}}}}})));
  std::vector<double> inks;
  for (double distance : {8.0, 11.0, 16.0}) {
    const RenderResult r = renderer.render(scene, front_camera({0, 0, distance}, size), settings(size));
    double sum = 0;
    for (size_t i = 0; i < r.color.size(); i += 4) sum += 1.0 - r.color[i];
    inks.push_back(sum / double(r.color.size() / 4));
  }
  EXPECT_GT(inks[0], 0.05);
  for (double v : inks) EXPECT_NEAR(v, inks[0], 0.35 * inks[0]) << inks[0] << " " << inks[1] << " " << inks[2];
}

}  // namespace
