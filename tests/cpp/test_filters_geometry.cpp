// Edge enhancement from depth: eye-dome lighting darkens surfaces just
// behind nearer ones, depth contours become lines, flat depth is untouched,
// silhouettes only around dense regions.
#include <gtest/gtest.h>

#include "filter_images.h"
#include "render/renderer.h"
#include "scene_builders.h"

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

TEST(FilterEdgeEnhance, DepthStepsWithinTheScansSpacingAreItsNoise) {
  // A Kinect wall: a plane facing the camera whose depth is quantised in
  // steps of 0.02 every 4 px (the sensor's disparity steps). Without the
  // scan's spacing EDL shades every step; with a spacing above the step the
  // wall stays clean, while the occlusion of a nearer square (5 units, far
  // beyond the spacing) is still shaded.
  Image wall({96, 64});
  wall.depth.assign(size_t(96 * 64), std::numeric_limits<float>::infinity());
  for (int y = 4; y < 60; ++y)
    for (int x = 4; x < 92; ++x) {
      wall.set(x, y, glm::vec4(0.6f, 0.6f, 0.6f, 1.0f));
      wall.depth[wall.index(x, y)] = 1.0f + 0.02f * float(x / 4);
    }
  const auto shaded = [](const Image& in, const Image& out) {
    int n = 0;
    for (int y = 8; y < 56; ++y)
      for (int x = 8; x < 88; ++x) n += out.at(x, y) != in.at(x, y);
    return n;
  };
  const std::map<std::string, std::vector<double>> edl{{"outline_width", {0}}, {"edl_strength", {1.0}}};
  EXPECT_GT(shaded(wall, run_filter(wall, "edge_enhance", edl).out), 48 * 15) << "each step shades a column";
  wall.spacing = 0.03f;
  EXPECT_EQ(shaded(wall, run_filter(wall, "edge_enhance", edl).out), 0);
  Image occluded = occlusion_image();
  occluded.spacing = 0.03f;
  EXPECT_LT(run_filter(occluded, "edge_enhance", edl).out.at(43, 48).b, 0.5f * occluded.at(43, 48).b);
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

// A roof seen from above: two planes meeting at a ridge along y (x = 0),
// each sloping 45 degrees, plus depth noise; no depth jump anywhere.
std::shared_ptr<PointCloud> roof_cloud(double noise) {
  std::vector<double> pos;
  std::vector<uint8_t> col;
  uint32_t i = 0;
  for (double y = -2.0; y <= 2.0; y += 0.015)
    for (double x = -2.0; x <= 2.0; x += 0.015, ++i) {
      const double jitter = noise * (double((i * 2654435761u >> 8) & 0xffff) / 65535.0 - 0.5);
      pos.insert(pos.end(), {x, y, -std::abs(x) + jitter});
      col.insert(col.end(), {180, 180, 180});
    }
  PointCloudInput in;
  in.positions = pos;
  in.colors = col;
  return std::make_shared<PointCloud>(in);
}

TEST(FilterEdgeEnhance, CreasesOutlineTheRidgeNotTheNoise) {
  const glm::ivec2 size(160, 120);
  const Camera cam = front_camera({0, 0, 8}, size);
  Renderer renderer;
  auto lines = [&](double crease_angle, double noise) {
    Scene scene;
    scene.segments.push_back(segment(
        "roof", roof_cloud(noise),
        style_with({{"point_size", {2}}},
                   {{"edge_enhance", {{"crease_angle", {crease_angle}}, {"edl_strength", {0}}, {"silhouette", {0}},
                                      {"edge_color", {1, 0, 0, 1}}}}})));
    const RenderResult r = renderer.render(scene, cam, settings(size));
    // Red pixels by column, over the rows in the middle.
    std::vector<int> per_column(size_t(size.x), 0);
    for (int y = 20; y < size.y - 20; ++y)
      for (int x = 0; x < size.x; ++x) {
        const float* c = &r.color[4 * (size_t(y) * size.x + size_t(x))];
        per_column[size_t(x)] += c[0] > 0.5f && c[1] < 0.2f;
      }
    return per_column;
  };
  const std::vector<int> ridge = lines(30.0, 0.004);
  const int centre = size.x / 2;
  int at_ridge = 0, elsewhere = 0;
  for (int x = 0; x < size.x; ++x) (std::abs(x - centre) <= 3 ? at_ridge : elsewhere) += ridge[size_t(x)];
  EXPECT_GE(at_ridge, 76) << "the ridge is outlined along its length (80 rows)";
  EXPECT_LE(at_ridge, 80 * 2) << "one pixel wide at outline_width 1";
  EXPECT_LT(elsewhere, at_ridge / 20) << "noise on the slopes makes no creases";
  int off = 0;
  for (int v : lines(0.0, 0.004)) off += v;
  EXPECT_EQ(off, 0) << "crease_angle 0 draws no creases";
  int shallow = 0;
  for (int v : lines(120.0, 0.004)) shallow += v;
  EXPECT_EQ(shallow, 0) << "a 90 degree ridge is not a 120 degree crease";
}

}  // namespace
