// The continuous resolution queue's order (render/gpu_cloud.h): per chunk a
// permutation of its points, set by point ids alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "render/attributes.h"
#include "render/gpu_cloud.h"
#include "scene/point_cloud.h"

namespace pointnpr {
namespace {

std::vector<double> grid(int n) {
  std::vector<double> xyz;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) xyz.insert(xyz.end(), {x * 0.01, y * 0.01, 0.0});
  return xyz;
}

TEST(ResolutionQueue, EachChunkGetsAPermutationOfItsPoints) {
  const std::vector<double> xyz = grid(120);  // 14400 points, several chunks of 4096
  PointCloudInput in;
  in.positions = xyz;
  const PointCloud cloud(in, 4096);
  ASSERT_GT(cloud.chunks().size(), 2u);
  const std::vector<uint32_t> order = queue_order(cloud);
  ASSERT_EQ(order.size(), cloud.size());
  for (const PointChunk& c : cloud.chunks()) {
    std::vector<uint32_t> local(order.begin() + c.first, order.begin() + c.first + c.count);
    std::sort(local.begin(), local.end());
    std::vector<uint32_t> expected(c.count);
    std::iota(expected.begin(), expected.end(), 0u);
    EXPECT_EQ(local, expected);
    // Seeded random, not the storage order: the first tenth is spread over the chunk.
    uint32_t first_tenth_max = 0;
    for (uint32_t i = 0; i < c.count / 10; ++i) first_tenth_max = std::max(first_tenth_max, order[c.first + i]);
    EXPECT_GT(first_tenth_max, c.count / 2);
  }
}

TEST(ResolutionQueue, OrderFollowsPointIdsNotInputOrder) {
  const std::vector<double> xyz = grid(60);
  const size_t n = xyz.size() / 3;
  std::vector<uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(7));
  std::vector<double> shuffled(xyz.size());
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) shuffled[3 * i + k] = xyz[3 * perm[i] + k];
  PointCloudInput a, b;
  a.positions = xyz;
  b.positions = shuffled;
  b.point_index = perm;
  const PointCloud ca(a, 1u << 20), cb(b, 1u << 20);  // one chunk each
  ASSERT_EQ(ca.chunks().size(), 1u);
  ASSERT_EQ(cb.chunks().size(), 1u);
  const std::vector<uint32_t> oa = queue_order(ca), ob = queue_order(cb);
  for (size_t j = 0; j < n; ++j) EXPECT_EQ(ca.point_index()[oa[j]], cb.point_index()[ob[j]]) << j;
}

TEST(ResolutionQueue, FeatureKeysPackNeighbourhoodsThresholdAndColourWeightSteps) {
  EXPECT_EQ(feature_line_key(48, 8, 0.35, 0.0).k, 48 + 100 * 8 + 10000 * 7);
  EXPECT_EQ(feature_line_key(48, 8, 0.35, 0.5), feature_line_key(48, 8, 0.399, 0.52));  // same 0.05 steps
  EXPECT_NE(feature_line_key(48, 8, 0.35, 0.5), feature_line_key(48, 8, 0.40, 0.5));
  EXPECT_NE(feature_line_key(48, 8, 0.35, 0.5), feature_line_key(48, 8, 0.35, 0.55));
  EXPECT_EQ(feature_line_key(48, 8, 1.0, 0.0).k / 10000, 20);
  EXPECT_EQ(to_string(feature_line_key(16, 8, 0.0, 0.0)), "feature_line:816");
  // The colour weight in both keys, decoded as the cache computes the degree.
  for (const double w : {0.0, 0.5, 0.95, 1.0}) {
    const FeatureDegreeSpec line = feature_degree_spec(feature_line_key(99, 64, 1.0, w));
    const FeatureDegreeSpec degree = feature_degree_spec(feature_degree_key(64, w));
    EXPECT_EQ(line.neighbors, 64);
    EXPECT_EQ(degree.neighbors, 64);
    EXPECT_FLOAT_EQ(line.color_weight, float(w));
    EXPECT_FLOAT_EQ(degree.color_weight, float(w));
  }
  EXPECT_EQ(feature_degree_key(8, 0.5), feature_degree_key(8, 0.54));
  // The line fit's own part, decoded as the cache computes the fit.
  const FeatureLineSpec spec = feature_line_spec(feature_line_key(48, 8, 0.37, 0.5));
  EXPECT_EQ(spec.line_neighbors, 48);
  EXPECT_FLOAT_EQ(spec.threshold, 0.35f);
  EXPECT_EQ(spec.degree.neighbors, 8);
  EXPECT_FLOAT_EQ(spec.degree.color_weight, 0.5f);
}

}  // namespace
}  // namespace pointnpr
