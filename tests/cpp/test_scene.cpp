#include <cmath>
#include <limits>
#include <algorithm>
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "scene/camera.h"
#include "core/morton.h"
#include "scene/point_cloud.h"

using namespace pointnpr;

TEST(PointCloud, ChunksKeepEveryPointAndItsStableIndex) {
  std::vector<double> pos;
  for (int i = 0; i < 50000; ++i) pos.insert(pos.end(), {double(i % 97), double(i % 89) * 0.5, double(i) * 1e-3});
  PointCloudInput in;
  in.positions = pos;
  PointCloud cloud(in, 4096);
  ASSERT_EQ(cloud.size(), 50000u);
  EXPECT_GE(cloud.chunks().size(), 13u);
  std::vector<int> seen(50000, 0);
  const auto back = cloud.positions_double();
  for (size_t k = 0; k < cloud.size(); ++k) {
    const uint32_t i = cloud.point_index()[k];
    ++seen[i];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[3 * k + size_t(c)], pos[3 * i + size_t(c)], 1e-4);
  }
  for (int s : seen) ASSERT_EQ(s, 1);
}

TEST(PointCloud, GeoreferencedCoordinatesKeepMillimetres) {
  // Aerial LiDAR in UTM: 1e6 m offsets. Float alone would round to 6 cm.
  std::vector<double> pos;
  for (int i = 0; i < 1000; ++i) pos.insert(pos.end(), {637000.123 + i * 0.001, 5e6 + 0.007 * i, 120.5});
  PointCloudInput in;
  in.positions = pos;
  PointCloud cloud(in, 256);
  const auto back = cloud.positions_double();
  for (size_t k = 0; k < cloud.size(); ++k) {
    const uint32_t i = cloud.point_index()[k];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[3 * k + size_t(c)], pos[3 * i + size_t(c)], 1e-5);
  }
}

TEST(PointCloud, LeavesOutNonFinitePointsAndKeepsTheOthersIds) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> pos = {0, 0, 0, 1, std::nan(""), 0, 2, 0, 0, 3, 0, -inf, 4, 0, 0};
  std::vector<uint8_t> colors = {10, 0, 0, 20, 0, 0, 30, 0, 0, 40, 0, 0, 50, 0, 0};
  PointCloudInput in;
  in.positions = pos;
  in.colors = colors;
  const PointCloud cloud(in);
  EXPECT_EQ(cloud.size(), 3u);
  EXPECT_EQ(cloud.skipped_nonfinite(), 2u);
  std::vector<uint32_t> ids = cloud.point_index();
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<uint32_t>{0, 2, 4}));
  for (size_t k = 0; k < cloud.size(); ++k)  // colours follow their points
    EXPECT_EQ(cloud.colors()[k] & 0xffu, 10u + 10u * cloud.point_index()[k]);
  EXPECT_EQ(cloud.bounds_max().x, 4.0);
  std::vector<double> all_nan = {std::nan(""), 0, 0};
  in.positions = all_nan;
  in.colors = {};
  const PointCloud empty(in);
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(empty.skipped_nonfinite(), 1u);
}

TEST(PointCloud, RejectsInconsistentInput) {
  std::vector<double> pos = {0, 0, 0, 1, 1};
  PointCloudInput in;
  in.positions = pos;
  EXPECT_THROW(PointCloud{in}, Error);
  std::vector<double> ok = {0, 0, 0};
  std::vector<uint8_t> colors = {1, 2};
  in.positions = ok;
  in.colors = colors;
  EXPECT_THROW(PointCloud{in}, Error);
}

TEST(PointCloud, NormalsFollowTheirPointsIntoChunkOrder) {
  std::vector<double> pos;
  std::vector<float> normals;
  for (int i = 0; i < 3000; ++i) {
    pos.insert(pos.end(), {double(i % 50), double(i / 50), 0.0});
    normals.insert(normals.end(), {float(i), 0.0f, 1.0f});
  }
  PointCloudInput in;
  in.positions = pos;
  in.normals = normals;
  PointCloud cloud(in, 512);
  ASSERT_TRUE(cloud.has(Attribute::Normal));
  for (size_t k = 0; k < cloud.size(); ++k) EXPECT_EQ(cloud.normals()[k].x, float(cloud.point_index()[k]));
}

TEST(PointCloud, EmptyCloudIsValid) {
  PointCloudInput in;
  PointCloud cloud(in);
  EXPECT_EQ(cloud.size(), 0u);
  EXPECT_TRUE(cloud.chunks().empty());
}

TEST(Camera, PerspectiveFollowsBlenderSensorFit) {
  // 50 mm lens on a 36 mm sensor: a point at x = 0.36 m, 1 m away, lands at
  // ndc x = 0.36 * 50 / 18 = 1.0 (the right image edge) for horizontal fit.
  const Camera c = Camera::perspective(glm::dmat4(1.0), 50, 36, 24, SensorFit::Auto, 0, 0, 0.1, 100, {1920, 1080});
  glm::dvec4 clip = c.projection * c.view_from_world * glm::dvec4(0.36, 0.0, -1.0, 1.0);
  EXPECT_NEAR(clip.x / clip.w, 1.0, 1e-12);
  // Portrait image: AUTO fits the sensor to the larger (vertical) side.
  const Camera p = Camera::perspective(glm::dmat4(1.0), 50, 36, 24, SensorFit::Auto, 0, 0, 0.1, 100, {1080, 1920});
  clip = p.projection * glm::dvec4(0.0, 0.36, -1.0, 1.0);
  EXPECT_NEAR(clip.y / clip.w, 1.0, 1e-12);
  // Vertical fit uses the sensor height.
  const Camera v = Camera::perspective(glm::dmat4(1.0), 50, 36, 24, SensorFit::Vertical, 0, 0, 0.1, 100, {1920, 1080});
  clip = v.projection * glm::dvec4(0.0, 0.24, -1.0, 1.0);
  EXPECT_NEAR(clip.y / clip.w, 1.0, 1e-12);
}

TEST(Camera, ShiftMovesTheImageByAFractionOfTheLargerSide) {
  const Camera c = Camera::perspective(glm::dmat4(1.0), 50, 36, 24, SensorFit::Auto, 0.25, 0, 0.1, 100, {1000, 500});
  const glm::dvec4 clip = c.projection * glm::dvec4(0.0, 0.0, -1.0, 1.0);
  EXPECT_NEAR(clip.x / clip.w, -0.5, 1e-12);  // shift 0.25 of 1000 px = 250 px = half the NDC half-width
}

TEST(Camera, OrthographicScaleSpansTheLargerSide) {
  const Camera c = Camera::orthographic_camera(glm::dmat4(1.0), 10.0, SensorFit::Auto, 0, 0, 0.1, 100, {800, 400});
  const glm::dvec4 clip = c.projection * glm::dvec4(5.0, 0.0, -3.0, 1.0);
  EXPECT_NEAR(clip.x / clip.w, 1.0, 1e-12);
  EXPECT_TRUE(c.orthographic);
}

TEST(Camera, FromMatricesRecoversTheClipRange) {
  const glm::dmat4 persp = glm::perspective(0.8, 1.5, 0.05, 250.0);
  const Camera c = Camera::from_matrices(glm::dmat4(1.0), persp);
  EXPECT_FALSE(c.orthographic);
  EXPECT_NEAR(c.clip_start, 0.05, 1e-9);
  EXPECT_NEAR(c.clip_end, 250.0, 1e-6);
  const Camera o = Camera::from_matrices(glm::dmat4(1.0), glm::ortho(-2.0, 2.0, -1.0, 1.0, 0.5, 80.0));
  EXPECT_TRUE(o.orthographic);
  EXPECT_NEAR(o.clip_start, 0.5, 1e-9);
  EXPECT_NEAR(o.clip_end, 80.0, 1e-9);
}

TEST(Camera, RejectsInvalidParameters) {
  EXPECT_THROW(Camera::perspective(glm::dmat4(1.0), 0, 36, 24, SensorFit::Auto, 0, 0, 0.1, 100, {10, 10}),
               ParameterError);
  EXPECT_THROW(Camera::perspective(glm::dmat4(1.0), 50, 36, 24, SensorFit::Auto, 0, 0, 1.0, 0.5, {10, 10}),
               ParameterError);
  EXPECT_THROW(Camera::perspective(glm::dmat4(1.0), 50, 36, 24, SensorFit::Auto, 0, 0, 0.1, 10, {0, 10}),
               ParameterError);
  EXPECT_THROW(parse_sensor_fit("SIDEWAYS"), ParameterError);
}

namespace {
// The layout the cloud had before its order was sorted in buckets: every
// finite point's (Morton code, index), sorted.
std::vector<uint32_t> reference_order(const std::vector<double>& pos) {
  const size_t n = pos.size() / 3;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  auto finite = [&](size_t i) {
    return std::isfinite(pos[3 * i]) && std::isfinite(pos[3 * i + 1]) && std::isfinite(pos[3 * i + 2]);
  };
  for (size_t i = 0; i < n; ++i)
    if (finite(i)) {
      lo = glm::min(lo, glm::dvec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
      hi = glm::max(hi, glm::dvec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
    }
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-12));
  const double scale = double((1u << 21) - 1) / std::max({extent.x, extent.y, extent.z});
  std::vector<std::pair<uint64_t, uint32_t>> keyed;
  for (size_t i = 0; i < n; ++i)
    if (finite(i))
      keyed.push_back({morton_code(uint64_t((pos[3 * i] - lo.x) * scale), uint64_t((pos[3 * i + 1] - lo.y) * scale),
                                   uint64_t((pos[3 * i + 2] - lo.z) * scale)),
                       uint32_t(i)});
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order;
  for (const auto& k : keyed) order.push_back(k.second);
  return order;
}
}  // namespace

TEST(PointCloud, BucketedMortonOrderIsTheFullSortsOrder) {
  // Sizes below and above the bucket threshold, clustered points (many in
  // one bucket), exact duplicates (equal codes: ties by index) and
  // non-finite points, which are left out.
  for (size_t n : {size_t(1), size_t(100), size_t(5000), size_t(300000)}) {
    std::vector<double> pos;
    for (size_t i = 0; i < n; ++i) {
      const double t = double((i * 2654435761u) % 100003) / 100003.0;
      if (i % 7 == 0)
        pos.insert(pos.end(), {1.0, 2.0, 3.0});                      // duplicates
      else if (i % 5 == 0)
        pos.insert(pos.end(), {1.0 + t * 1e-3, 2.0, 3.0 + t * 1e-3});  // a tight cluster
      else
        pos.insert(pos.end(), {t * 100.0, std::fmod(t * 7919.0, 60.0), t * t * 15.0});
      if (i % 1013 == 1) pos[pos.size() - 2] = std::numeric_limits<double>::quiet_NaN();
    }
    PointCloudInput in;
    in.positions = pos;
    PointCloud cloud(in, 4096);
    EXPECT_EQ(cloud.point_index(), reference_order(pos)) << n << " points";
  }
}

TEST(PointCloud, Float32PositionsGiveTheCloudOfTheirFloat64Values) {
  std::vector<float> pos32;
  for (int i = 0; i < 40000; ++i)
    pos32.insert(pos32.end(), {float(i % 211) * 0.37f, float(i % 173) * 0.11f - 5.0f, float(i) * 1e-4f});
  pos32[3 * 17] = std::numeric_limits<float>::infinity();
  const std::vector<double> pos64(pos32.begin(), pos32.end());
  PointCloudInput a, b;
  a.positions = pos64;
  b.positions_f32 = pos32;
  PointCloud from64(a, 1024), from32(b, 1024);
  EXPECT_EQ(from32.skipped_nonfinite(), 1u);
  EXPECT_EQ(from32.point_index(), from64.point_index());
  ASSERT_EQ(from32.chunks().size(), from64.chunks().size());
  for (size_t c = 0; c < from32.chunks().size(); ++c) EXPECT_EQ(from32.chunks()[c].origin, from64.chunks()[c].origin);
  EXPECT_EQ(from32.local_positions(), from64.local_positions());
  EXPECT_EQ(from32.bounds_min(), from64.bounds_min());
  EXPECT_EQ(from32.bounds_max(), from64.bounds_max());

  PointCloudInput both;
  both.positions = pos64;
  both.positions_f32 = pos32;
  EXPECT_THROW(PointCloud{both}, Error);
}
