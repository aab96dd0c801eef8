// The points mark's native rasterizer (marks/points/native.cpp): the
// compute rasterizer's images, whatever the number of threads.
#include <gtest/gtest.h>

#include <cstring>

#include <tbb/global_control.h>

#include "marks/points/points.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

constexpr glm::ivec2 kSize{320, 240};

Scene two_planes(RasterizerKind kind, double near_size, double far_size) {
  Scene scene;
  scene.segments.push_back(segment("a", plane_cloud(-1.2, 0.4, -0.6, 0.6, -5, 0.03, {230, 60, 40}, {}, 0.02),
                                   style_with({{"point_size", {near_size}}})));
  scene.segments.push_back(segment("b", plane_cloud(-2, 3, -1.5, 1.5, -10, 0.11, {40, 60, 230}, {}, 0.05),
                                   style_with({{"point_size", {far_size}}})));
  return with_rasterizer(scene, kind);
}

bool same_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

}  // namespace

TEST(NativeRasterizer, AgreesWithComputeWithinTheirTolerance) {
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize);
  for (const auto& [near_size, far_size] : {std::pair{3.0, 5.0}, {1.0, 1.5}, {2.0, 0.8}}) {
    const RenderResult c =
        renderer.render(two_planes(RasterizerKind::Compute, near_size, far_size), cam, settings(kSize, "depth_test"));
    const RenderResult n =
        renderer.render(two_planes(RasterizerKind::Native, near_size, far_size), cam, settings(kSize, "depth_test"));
    size_t either = 0, mismatch = 0;
    for (size_t i = 0; i < c.segment_index.size(); ++i) {
      const bool cc = c.color[4 * i + 3] > 0, nc = n.color[4 * i + 3] > 0;
      either += cc || nc;
      const bool same = cc == nc && c.segment_index[i] == n.segment_index[i] && c.depth[i] == n.depth[i] &&
                        std::memcmp(&c.color[4 * i], &n.color[4 * i], 16) == 0;
      mismatch += !same;
    }
    ASSERT_GT(either, 3000u);
    // The tolerance between compute and gl_points (test_render.cpp): 0.5 %.
    EXPECT_LE(mismatch * 200, either) << mismatch << " of " << either << " at " << near_size << " px";
  }
}

TEST(NativeRasterizer, SameBytesWithOneOrTwoThreads) {
  const Camera cam = front_camera({0, 0, 0}, kSize);
  const Scene scene = two_planes(RasterizerKind::Native, 2.5, 1.0);
  std::vector<RenderResult> results;
  for (size_t threads : {size_t(1), size_t(2), size_t(1)}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Renderer renderer;
    results.push_back(renderer.render(scene, cam, settings(kSize, "inpaint")));
  }
  for (size_t i = 1; i < results.size(); ++i) {
    EXPECT_TRUE(same_bytes(results[0].color, results[i].color));
    EXPECT_TRUE(same_bytes(results[0].depth, results[i].depth));
    EXPECT_EQ(results[0].segment_index, results[i].segment_index);
  }
  size_t covered = 0;
  for (int32_t idx : results[0].segment_index) covered += idx >= 0;
  EXPECT_GT(covered, 5000u);
}

TEST(NativeRasterizer, CoveredBoundsItReportsAreTheDepthPassOnes) {
  // The renderer takes the covered bounds from the native rasterizer
  // instead of its depth pass; filters run within them, so a filter whose
  // output reaches the image border shows any bound that is too tight.
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize);
  Scene scene;
  scene.segments.push_back(segment("a", plane_cloud(-1.2, 0.4, -0.6, 0.6, -5, 0.03, {230, 60, 40}, {}, 0.02),
                                   style_with({{"point_size", {3}}}, {{"cartoon", {}}})));
  const RenderResult c = renderer.render(with_rasterizer(scene, RasterizerKind::Compute), cam, settings(kSize));
  const RenderResult n = renderer.render(with_rasterizer(scene, RasterizerKind::Native), cam, settings(kSize));
  size_t covered = 0, mismatch = 0;
  for (size_t i = 0; i < c.segment_index.size(); ++i) {
    covered += c.segment_index[i] >= 0;
    mismatch += c.segment_index[i] != n.segment_index[i] || std::memcmp(&c.color[4 * i], &n.color[4 * i], 16) != 0;
  }
  ASSERT_GT(covered, 10000u);
  EXPECT_LE(mismatch * 200, covered) << mismatch << " of " << covered;
}

// The native colour of each source (shaders/point_color.glsl, compiled
// for the host): packed RGBA8, scaled and clamped intensity, the ASPRS
// palette with gray beyond it, the constant colour; alpha always 1.
TEST(NativeRasterizer, HostColorsReadEachSource) {
  const uint32_t rgb[1] = {0x80ff4000u};  // r 0x00, g 0x40, b 0xff, a 0x80
  const float intensity[2] = {0.25f, 3.0f};
  const uint32_t classes[4] = {2u, 9u, 19u, 100000u};
  HostColors c;
  c.colors = rgb;
  c.intensity = intensity;
  c.classification = classes;
  c.intensity_scale = 2.0f;
  c.constant = glm::vec4(0.1f, 0.2f, 0.3f, 0.4f);
  c.source = ColorSource::Rgb;
  EXPECT_EQ(c.at(0), glm::vec4(0.0f, 64.0f / 255.0f, 1.0f, 1.0f));
  c.source = ColorSource::Intensity;
  EXPECT_EQ(c.at(0), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  EXPECT_EQ(c.at(1), glm::vec4(1.0f));  // clamped
  c.source = ColorSource::Classification;
  EXPECT_EQ(c.at(0), glm::vec4(0.63f, 0.48f, 0.33f, 1.0f));  // ground
  EXPECT_EQ(c.at(1), glm::vec4(0.25f, 0.50f, 0.90f, 1.0f));  // water
  EXPECT_EQ(c.at(2), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));     // past the palette
  EXPECT_EQ(c.at(3), glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  c.source = ColorSource::Constant;
  EXPECT_EQ(c.at(0), glm::vec4(0.1f, 0.2f, 0.3f, 1.0f));
}
