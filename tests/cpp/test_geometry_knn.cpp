// The all-points kNN (geometry/neighbors.cpp) against brute force: the same
// rows, bit for bit, on every kind of cloud that sends the grid search down
// a different path (dense and sparse regions, far outliers, ties, piles of
// duplicates, piles finer than the finest grid cell, tiny clouds).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <random>

#include "core/error.h"
#include "geometry/local_points.h"
#include "geometry/neighbors.h"

using namespace pointnpr;
using namespace pointnpr::geometry;

namespace {

std::vector<double> xyz_of(const std::vector<glm::dvec3>& p) {
  std::vector<double> out;
  for (const auto& v : p) out.insert(out.end(), {v.x, v.y, v.z});
  return out;
}

// The definition: the k smallest by (float squared distance, index), with
// the distance computed as the search computes it.
void expect_brute_force_rows(const LocalPoints& lp, const Neighborhoods& nb, int k_requested) {
  const size_t n = lp.size(), k = std::min<size_t>(size_t(k_requested), n);
  ASSERT_EQ(size_t(nb.k), k);
  std::vector<std::pair<float, uint32_t>> all(n);
  size_t bad = 0;
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 p = lp.points[i];
    for (size_t j = 0; j < n; ++j) {
      const float dx = p.x - lp.points[j].x, dy = p.y - lp.points[j].y, dz = p.z - lp.points[j].z;
      all[j] = {dx * dx + dy * dy + dz * dz, uint32_t(j)};
    }
    std::partial_sort(all.begin(), all.begin() + long(k), all.end());
    for (size_t j = 0; j < k; ++j)
      if (nb.at(i)[j] != all[j].second || nb.d2_at(i)[j] != all[j].first) {
        if (++bad <= 3)
          ADD_FAILURE() << "point " << i << " neighbour " << j << ": (" << nb.d2_at(i)[j] << ", " << nb.at(i)[j]
                        << ") instead of (" << all[j].first << ", " << all[j].second << ")";
        break;
      }
  }
  EXPECT_EQ(bad, 0u);
}

void expect_exact(const std::vector<glm::dvec3>& cloud, std::initializer_list<int> ks) {
  const LocalPoints lp = LocalPoints::from(xyz_of(cloud));
  for (int k : ks) {
    SCOPED_TRACE("k = " + std::to_string(k));
    expect_brute_force_rows(lp, knn_all(lp, k), k);
  }
}

}  // namespace

TEST(GeometryKnn, ExactOnAVolumeAndOnTerrainOfVaryingDensity) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec3> volume;
  for (int i = 0; i < 3000; ++i) volume.push_back({u(rng), u(rng), u(rng)});
  expect_exact(volume, {1, 6, 16, 40});

  // 2.5-D aerial-like: a dense patch 50x the density of the rest, bumps in z.
  std::vector<glm::dvec3> terrain;
  for (int i = 0; i < 2500; ++i) {
    const double x = 100.0 * u(rng), y = 100.0 * u(rng);
    terrain.push_back({x, y, 2.0 * std::sin(x * 0.1) + 0.05 * u(rng)});
  }
  for (int i = 0; i < 2500; ++i) {
    const double x = 40.0 + 6.0 * u(rng), y = 40.0 + 6.0 * u(rng);
    terrain.push_back({x, y, 2.0 * std::sin(x * 0.1) + 0.05 * u(rng)});
  }
  expect_exact(terrain, {10, 30});
}

TEST(GeometryKnn, ExactWithFarOutliersAndTinyClusters) {
  // Lone points far from two dense clusters search coarse levels and large
  // blocks; pairs of points whose k-th neighbour is in another cluster.
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<glm::dvec3> cloud;
  for (int i = 0; i < 2000; ++i) cloud.push_back({0.01 * g(rng), 0.01 * g(rng), 0.01 * g(rng)});
  for (int i = 0; i < 2000; ++i) cloud.push_back({500.0 + 0.01 * g(rng), 0.01 * g(rng), 0.01 * g(rng)});
  for (int i = 0; i < 40; ++i) cloud.push_back({300.0 * g(rng), 300.0 * g(rng), 300.0 * g(rng)});
  for (int i = 0; i < 3; ++i) cloud.push_back({250.0 + i * 1e-3, 250.0, 0.0});
  expect_exact(cloud, {4, 20});
}

TEST(GeometryKnn, TiesGoToTheLowerIndex) {
  // A unit lattice: every point has many neighbours at exactly equal
  // distances, so the k-th neighbour is decided by index alone.
  std::vector<glm::dvec3> lattice;
  for (int x = 0; x < 14; ++x)
    for (int y = 0; y < 14; ++y)
      for (int z = 0; z < 6; ++z) lattice.push_back({x, y, z});
  expect_exact(lattice, {2, 7, 19, 27});
}

TEST(GeometryKnn, PilesOfDuplicatesAnswerWithTheFirstOfThePile) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<glm::dvec3> cloud;
  for (int i = 0; i < 1500; ++i) cloud.push_back({u(rng), u(rng), u(rng)});
  // A scanner's invalid returns at one spot, shuffled among the others, and
  // a few points doubled (fewer copies than k).
  for (int i = 0; i < 3000; ++i) cloud.push_back({0.25, -0.5, 0.125});
  for (int i = 0; i < 20; ++i) cloud.push_back(cloud[size_t(7 * i)]);
  std::shuffle(cloud.begin(), cloud.end(), rng);
  const LocalPoints lp = LocalPoints::from(xyz_of(cloud));
  // Identical points are adjacent after the Morton sort.
  std::map<std::tuple<float, float, float>, std::vector<size_t>> where;
  for (size_t s = 0; s < lp.size(); ++s) where[{lp.points[s].x, lp.points[s].y, lp.points[s].z}].push_back(s);
  for (const auto& [point, at] : where) EXPECT_EQ(at.back() - at.front() + 1, at.size());
  EXPECT_EQ(where.size(), 1501u);
  expect_brute_force_rows(lp, knn_all(lp, 12), 12);
  expect_brute_force_rows(lp, knn_all(lp, 1), 1);
}

TEST(GeometryKnn, ExactOnAPileFinerThanTheFinestCell) {
  // 6000 distinct points within a micrometre (near the local origin, where
  // floats resolve them), 1 km from the other two points: one finest cell
  // (1 mm) holds them all, beyond the brute-force budget, so most of them
  // are answered by the k-d tree; the answer is the same.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-6, 1e-6);
  std::vector<glm::dvec3> cloud;
  for (int i = 0; i < 6000; ++i) cloud.push_back({0.2 + u(rng), u(rng), u(rng)});
  cloud.push_back({-1000.0, 0.0, 0.0});
  cloud.push_back({1000.0, 0.0, 0.0});
  const LocalPoints lp = LocalPoints::from(xyz_of(cloud));
  std::vector<glm::vec3> distinct(lp.points);
  std::sort(distinct.begin(), distinct.end(), [](auto a, auto b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); });
  EXPECT_GT(std::unique(distinct.begin(), distinct.end()) - distinct.begin(), 5900);
  expect_brute_force_rows(lp, knn_all(lp, 8), 8);
}

TEST(GeometryKnn, SmallCloudsAndKAtLeastN) {
  expect_exact({{0, 0, 0}}, {1, 5});
  expect_exact({{0, 0, 0}, {1, 0, 0}}, {1, 2, 3});
  std::vector<glm::dvec3> line;
  for (int i = 0; i < 37; ++i) line.push_back({0.5 * i, 0.25 * i, -0.125 * i});
  expect_exact(line, {1, 5, 36, 37, 100});
  EXPECT_TRUE(knn_all(LocalPoints::from(std::vector<double>{}), 4).index.empty());
  EXPECT_THROW(knn_all(LocalPoints::from(xyz_of(line)), 0), Error);
}

TEST(GeometryKnn, TheSameBytesWithOneThreadOrMany) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::vector<glm::dvec3> cloud;
  for (int i = 0; i < 40000; ++i) cloud.push_back({u(rng), u(rng), 0.1 * u(rng)});
  const LocalPoints lp = LocalPoints::from(xyz_of(cloud));
  const Neighborhoods many = knn_all(lp, 16);
  Neighborhoods one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = knn_all(lp, 16);
  }
  EXPECT_EQ(one.index, many.index);
  EXPECT_EQ(one.dist2, many.dist2);
}
