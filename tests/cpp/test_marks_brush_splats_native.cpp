// The brush_splats mark's native kernels (cpp/marks/brush_splats/native_*):
// one Highway source compiled for every SIMD target. Each target this CPU
// runs (one lane on the scalar target, four on SSE4, eight on AVX2 and
// AVX-512, which also take the brush pieces from a register permutation
// rather than a gather) draws the same bytes, over the paths a frame can
// take: perspective and orthographic, blur and none, one and two layers,
// clusters, the falloff's table and its pieces, candidates kept or a bin
// blended apart, one batch or several.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include <hwy/highway.h>

#include "render/mark.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

constexpr glm::ivec2 kSize{256, 192};
using Params = std::map<std::string, std::vector<double>>;

double item(const std::string& param, const std::string& value) {
  const auto& items = find_mark("brush_splats").schema.find(param)->items;
  return double(std::find(items.begin(), items.end(), value) - items.begin());
}

// A coloured cap of a sphere (normals all around) before a grey wall.
std::shared_ptr<PointCloud> cap_cloud() {
  std::vector<double> pos;
  std::vector<uint8_t> col;
  const int n = 12000;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - double(i) / double(n - 1), r = std::sqrt(1.0 - z * z), a = 2.399963 * i;
    pos.insert(pos.end(), {r * std::cos(a), r * std::sin(a), z - 5.0});
    col.insert(col.end(), {uint8_t(128 + 127 * r * std::cos(a)), uint8_t(128 + 127 * r * std::sin(a)), uint8_t(255 * z)});
  }
  PointCloudInput in;
  in.positions = pos;
  in.colors = col;
  return std::make_shared<PointCloud>(in);
}

Scene scene(Params params) {
  params["rasterizer"] = {item("rasterizer", "native")};
  Style style;
  style.set_mark("brush_splats", params);
  Scene s;
  s.segments.push_back(segment("s", cap_cloud(), style));
  s.segments[0].instances.push_back({plane_cloud(-2.0, 2.0, -1.5, 1.5, -6.5, 0.03, {150, 150, 150}, {}, 0.02),
                                     glm::dmat4(1.0)});
  return s;
}

struct Case {
  Params params;
  bool ortho = false;
  NativeLimits limits;
};

std::vector<Case> cases() {
  NativeLimits batches;
  batches.batch_splats = 1;  // a batch a chunk: depth passes, then blend passes
  batches.max_bins = 5;         // wide bins cut
  return {
      {{}},
      {{{"blending", {item("blending", "none")}}, {"size_scale", {8.0}}, {"max_radius", {40.0}}}},  // bins over their candidates
      {{{"layers", {item("layers", "two")}}, {"layer_tint", {-0.3}}, {"clusters", {1}}, {"small_cluster", {400}}}},
      {{{"lambda", {0.6}}}},  // steep at 0: the table over sqrt(q)
      {{{"lambda", {4.0}}, {"blur_radius", {5}}}},
      {{{"tangent_frame", {item("tangent_frame", "covariance")}}}, true},
      {{{"size_mode", {item("size_mode", "world")}}, {"world_radius", {0.05}}}, false, batches},
  };
}

std::vector<float> frame(Renderer& renderer, const Case& c, std::map<std::string, double>& stats) {
  Camera cam = front_camera({0.3, 0.2, 0}, kSize);
  if (c.ortho) {
    glm::dmat4 world_from_camera(1.0);
    world_from_camera[3] = glm::dvec4(0.3, 0.2, 0.0, 1.0);
    cam = Camera::orthographic_camera(world_from_camera, 4.0, SensorFit::Auto, 0.0, 0.0, 0.1, 100.0, kSize);
  }
  RenderSettings settings = test::settings(kSize);
  settings.native = c.limits;
  const RenderResult r = renderer.render(scene(c.params), cam, settings);
  stats = r.stats;
  std::vector<float> bytes = r.color;
  bytes.insert(bytes.end(), r.depth.begin(), r.depth.end());
  return bytes;
}

TEST(BrushSplatsNative, EverySimdTargetDrawsTheSameBytes) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_GE(targets.size(), 2u);  // (x86-64: at least SSE4 and the scalar target)
  Renderer renderer;
  const std::vector<Case> all = cases();
  std::vector<std::vector<float>> first;
  std::set<double> lanes_seen, degrees;
  int apart = 0, batches = 0;
  for (int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    for (size_t i = 0; i < all.size(); ++i) {
      std::map<std::string, double> stats;
      const std::vector<float> bytes = frame(renderer, all[i], stats);
      lanes_seen.insert(stats.at("brush_native_lanes"));
      if (first.size() <= i) {
        apart += stats.at("brush_native_bins_blended_apart") > 0.0;
        batches += stats.at("brush_native_batches") > 1.0;
        degrees.insert(stats.at("brush_native_falloff_degree"));
        size_t covered = 0;
        for (size_t p = 3; p < size_t(kSize.x * kSize.y) * 4; p += 4) covered += bytes[p] > 0.0f;
        EXPECT_GT(covered, size_t(kSize.x * kSize.y) / 4) << "case " << i;
        first.push_back(bytes);
        continue;
      }
      EXPECT_EQ(0, std::memcmp(first[i].data(), bytes.data(), bytes.size() * sizeof(float)))
          << "case " << i << " on " << hwy::TargetName(target);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_TRUE(lanes_seen.count(1.0));  // the scalar target ran
  EXPECT_GE(lanes_seen.size(), 2u);    // and one with vectors
  // The paths the cases are there for were taken.
  EXPECT_GT(apart, 0);
  EXPECT_GT(batches, 0);
  EXPECT_TRUE(degrees.count(0.0)) << "the falloff's table";
  EXPECT_GE(degrees.size(), 2u) << "its pieces";
}

}  // namespace
