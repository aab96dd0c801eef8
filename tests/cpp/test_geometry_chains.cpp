// Feature chains (geometry/feature_chains.h): the feature points along a
// line become one chain through its gaps; parallel lines, blobs and short
// specks do not link.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/analysis.h"
#include "geometry/feature_chains.h"

using namespace pointnpr;
using namespace pointnpr::geometry;

namespace {

struct Cloud {
  std::vector<double> xyz;
  std::vector<int> part;  // which shape a point belongs to
  void add(double x, double y, double z, int p) {
    xyz.insert(xyz.end(), {x, y, z});
    part.push_back(p);
  }
  size_t size() const { return part.size(); }
  glm::dvec3 at(size_t i) const { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }
};

// The root a point's parents lead to (the point itself for a root or an
// unchained point); fails on a loop.
size_t root_of(const LineFit& f, const Cloud& c, size_t i) {
  for (size_t steps = 0; steps <= c.size(); ++steps) {
    if (f.to_parent[i] == glm::vec3(0.0f)) return i;
    const glm::dvec3 parent = c.at(i) + glm::dvec3(f.to_parent[i]);
    size_t next = c.size();
    for (size_t j = 0; j < c.size(); ++j)
      if (glm::length(c.at(j) - parent) < 1e-5) next = j;
    if (next == c.size()) {
      ADD_FAILURE() << "point " << i << "'s parent is no point of the cloud";
      return i;
    }
    i = next;
  }
  ADD_FAILURE() << "the parents of point " << i << " loop";
  return i;
}

}  // namespace

TEST(GeometryChains, ALineBecomesOneChainThroughItsGapsAndNothingElseLinks) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  Cloud c;
  const double step = 1.0;
  // 0: an arc of radius 60 with every 8th and 9th sample missing (gaps of
  // three steps), jittered by a tenth of a step.
  for (int i = 0; i < 120; ++i)
    if (i % 9 != 7 && i % 9 != 8) {
      const double a = i * step / 60.0;
      c.add(60.0 * std::cos(a) + jitter(rng), 60.0 * std::sin(a) + jitter(rng), jitter(rng), 0);
    }
  // 1, 4: two straight lines side by side, 7 steps apart (within a link's
  // reach, but across the lines), with gaps as the arc's.
  for (int i = 0; i < 90; ++i)
    if (i % 9 != 7 && i % 9 != 8)
      for (int line : {1, 4}) c.add(i * step + jitter(rng), (line == 4 ? 7.0 : 0.0) + jitter(rng), 100.0, line);
  // 2: a scattered blob, far away.
  std::uniform_real_distribution<double> blob(-4.0, 4.0);
  for (int i = 0; i < 300; ++i) c.add(200 + blob(rng), blob(rng), blob(rng), 2);
  // 3: a speck: four points in a row (shorter than a chain's least length).
  for (int i = 0; i < 4; ++i) c.add(-100.0 + i * step, 0.0, 0.0, 3);

  Analysis a(c.xyz);
  const LineFit f = a.line_fit({}, 6);
  ASSERT_EQ(f.to_parent.size(), c.size());
  std::vector<size_t> roots[5];
  auto is_line = [](int part) { return part == 0 || part == 1 || part == 4; };
  for (size_t i = 0; i < c.size(); ++i) {
    const size_t r = root_of(f, c, i);
    EXPECT_EQ(c.part[r], c.part[i]) << "point " << i << " links to another shape";
    if (is_line(c.part[i])) roots[c.part[i]].push_back(r);
    if (!is_line(c.part[i])) {
      EXPECT_EQ(f.to_parent[i], glm::vec3(0.0f)) << "a " << (c.part[i] == 2 ? "blob" : "speck") << " point is chained";
    }
  }
  for (int part : {0, 1, 4}) {
    ASSERT_FALSE(roots[part].empty());
    for (size_t r : roots[part]) EXPECT_EQ(r, roots[part][0]) << "line " << part << " is not one chain";
  }
  // Links run along the lines, and each line has exactly two free ends.
  int ends[5] = {0, 0, 0, 0, 0};
  for (size_t i = 0; i < c.size(); ++i) {
    if (!is_line(c.part[i]) || f.to_parent[i] == glm::vec3(0.0f)) continue;
    const glm::dvec3 along = c.part[i] != 0 ? glm::dvec3(1, 0, 0) : glm::normalize(glm::dvec3(-c.at(i).y, c.at(i).x, 0));
    EXPECT_GT(std::abs(glm::dot(glm::normalize(glm::dvec3(f.to_parent[i])), along)), 0.8) << "point " << i;
    EXPECT_LE(glm::length(f.to_parent[i]), 3.5f * step);
    ends[c.part[i]] += (f.chain_end[i] & kChainEnd ? 1 : 0) + (f.chain_end[i] & kChainParentEnd ? 1 : 0);
  }
  for (int part : {0, 1, 4}) EXPECT_EQ(ends[part], 2) << "line " << part;
}
