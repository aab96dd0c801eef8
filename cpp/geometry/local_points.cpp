#include "geometry/local_points.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "core/morton.h"

namespace pointnpr::geometry {

LocalPoints LocalPoints::from(std::span<const double> xyz) {
  if (xyz.size() % 3 != 0) throw Error("positions must be an N x 3 array");
  const size_t n = xyz.size() / 3;
  if (n >= (size_t(1) << 31)) throw Error("point cloud too large (2^31 points or more)");
  LocalPoints lp;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 q(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      throw Error("point " + std::to_string(i) + " has a non-finite coordinate");
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  if (n == 0) return lp;
  lp.origin = (lo + hi) * 0.5;
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-300));
  const double scale = double((1u << 21) - 1) / std::max({extent.x, extent.y, extent.z});
  std::vector<std::pair<uint64_t, uint32_t>> order(n);
  std::vector<glm::vec3> local(n);
  tbb::parallel_for(size_t(0), n, size_t(4096), [&](size_t b) {
    for (size_t i = b; i < std::min(n, b + 4096); ++i) {
      const auto q = [&](int a) { return uint64_t(std::clamp((xyz[3 * i + a] - lo[a]) * scale, 0.0, 2097151.0)); };
      order[i] = {morton_code(q(0), q(1), q(2)), uint32_t(i)};
      local[i] = glm::vec3(glm::dvec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]) - lp.origin);
    }
  });
  // By code; within a code (rare, short runs but for duplicates) by
  // coordinates, then index: identical points end up adjacent, which the
  // kNN relies on to answer piles of duplicates in O(k).
  tbb::parallel_sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first < b.first;
    const glm::vec3 &p = local[a.second], &q = local[b.second];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a.second < b.second;
  });
  lp.grid_min = lo;
  lp.grid_scale = scale;
  lp.points.resize(n);
  lp.original.resize(n);
  lp.code.resize(n);
  for (size_t s = 0; s < n; ++s) {
    lp.code[s] = order[s].first;
    lp.original[s] = order[s].second;
    lp.points[s] = local[order[s].second];
  }
  return lp;
}

}  // namespace pointnpr::geometry
