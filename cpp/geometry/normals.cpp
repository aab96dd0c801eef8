#include "geometry/normals.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>

#include "core/progress.h"

namespace pointnpr::geometry {

PcaResult pca(const LocalPoints& pts, const Neighborhoods& nb) {
  const size_t n = pts.size();
  PcaResult r;
  r.normal.resize(n);
  r.curvature.resize(n);
  r.major.resize(n);
  r.linear_error.resize(n);
  r.degenerate.assign(n, 0);
  Progress* progress = current_progress();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& range) {
    check_cancelled(progress);
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const uint32_t* idx = nb.at(i);
      const int k = nb.k;
      // Offsets from the point itself keep the sums small; one pass in
      // double over the six distinct products.
      const glm::dvec3 p0(pts.points[i]);
      double sx = 0, sy = 0, sz = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
      for (int j = 0; j < k; ++j) {
        const glm::dvec3 d = glm::dvec3(pts.points[idx[j]]) - p0;
        sx += d.x;
        sy += d.y;
        sz += d.z;
        xx += d.x * d.x;
        xy += d.x * d.y;
        xz += d.x * d.z;
        yy += d.y * d.y;
        yz += d.y * d.z;
        zz += d.z * d.z;
      }
      const double inv = 1.0 / double(std::max(k, 1));
      const double mx = sx * inv, my = sy * inv, mz = sz * inv;
      Eigen::Matrix3d cov;
      cov(0, 0) = xx - sx * mx;
      cov(1, 1) = yy - sy * my;
      cov(2, 2) = zz - sz * mz;
      cov(0, 1) = cov(1, 0) = xy - sx * my;
      cov(0, 2) = cov(2, 0) = xz - sx * mz;
      cov(1, 2) = cov(2, 1) = yz - sy * mz;
      const double trace = cov.trace();
      if (!(trace > 1e-300)) {
        r.normal[i] = glm::vec3(0, 0, 1);
        r.major[i] = glm::vec3(1, 0, 0);
        r.curvature[i] = 0.0f;
        r.linear_error[i] = 0.0f;
        r.degenerate[i] = 1;
        continue;
      }
      cov /= trace;
      // Closed form first, accepted only with a certificate: by Davis-Kahan
      // the eigenvector's angular error is at most |A v - l v| / gap, so the
      // result stands when that bound is below 1e-7 rad for the smallest and
      // the largest eigenvector; otherwise (nearly isotropic or nearly
      // degenerate neighbourhoods) the iterative QR solver decides.
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
      es.computeDirect(cov, Eigen::ComputeEigenvectors);
      bool ok = es.info() == Eigen::Success && es.eigenvalues().allFinite() && es.eigenvectors().allFinite();
      if (ok) {
        const Eigen::Vector3d& l = es.eigenvalues();
        const double gap0 = l[1] - l[0], gap2 = l[2] - l[1];
        const double res0 = (cov * es.eigenvectors().col(0) - l[0] * es.eigenvectors().col(0)).norm();
        const double res2 = (cov * es.eigenvectors().col(2) - l[2] * es.eigenvectors().col(2)).norm();
        ok = res0 <= 1e-7 * gap0 && res2 <= 1e-7 * gap2 && std::abs(es.eigenvectors().col(0).norm() - 1.0) < 1e-9;
      }
      if (!ok) es.compute(cov, Eigen::ComputeEigenvectors);
      Eigen::Vector3d l = es.eigenvalues().cwiseMax(0.0);
      const double lsum = std::max(l.sum(), 1e-300);
      const Eigen::Vector3d v0 = es.eigenvectors().col(0).normalized();
      const Eigen::Vector3d v2 = es.eigenvectors().col(2).normalized();
      r.normal[i] = glm::vec3(float(v0.x()), float(v0.y()), float(v0.z()));
      r.major[i] = glm::vec3(float(v2.x()), float(v2.y()), float(v2.z()));
      r.curvature[i] = float(l[0] / lsum);
      r.linear_error[i] = float((l[0] + l[1]) / lsum);
    }
    advance(progress, range.size());
  });
  return r;
}

void orient(const LocalPoints& pts, const Neighborhoods& nb, std::vector<glm::vec3>& normals, Orientation how,
            const glm::dvec3& target, const std::optional<glm::dvec3>& sensor) {
  const size_t n = pts.size();
  if (how == Orientation::None || n == 0) return;
  if (how == Orientation::TowardPoint || how == Orientation::Direction) {
    const glm::dvec3 t = how == Orientation::TowardPoint ? target - pts.origin : target;
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      const glm::dvec3 d = how == Orientation::TowardPoint ? t - glm::dvec3(pts.points[i]) : t;
      if (glm::dot(glm::dvec3(normals[i]), d) < 0.0) normals[i] = -normals[i];
    });
    return;
  }
  // Consistent: Prim's algorithm on the symmetric kNN graph.
  std::vector<uint32_t> start(n + 1, 0), adj;
  const int k = std::min(nb.k, 10);  // the 10 nearest suffice to connect a surface
  for (size_t i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      const uint32_t o = nb.at(i)[j];
      if (o == i) continue;
      ++start[i + 1];
      ++start[o + 1];
    }
  for (size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  adj.resize(start[n]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      const uint32_t o = nb.at(i)[j];
      if (o == i) continue;
      adj[fill[i]++] = o;
      adj[fill[o]++] = uint32_t(i);
    }
  std::vector<uint32_t> by_height(n);
  std::iota(by_height.begin(), by_height.end(), 0u);
  std::stable_sort(by_height.begin(), by_height.end(),
                   [&](uint32_t a, uint32_t b) { return pts.points[a].z > pts.points[b].z; });
  std::vector<uint8_t> done(n, 0);
  // Prim's algorithm with a bucket queue: weights 1-|ni.nj| in [0,1]
  // quantised to 1/1024 (exact Prim on the quantised weights), O(1) per edge.
  constexpr int kBuckets = 1024;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> buckets(kBuckets);
  int lowest = kBuckets;
  auto visit = [&](uint32_t v) {
    done[v] = 1;
    for (uint32_t e = start[v]; e < start[v + 1]; ++e) {
      const uint32_t o = adj[e];
      if (done[o]) continue;
      const float w = 1.0f - std::abs(glm::dot(normals[v], normals[o]));
      const int b = std::clamp(int(w * float(kBuckets)), 0, kBuckets - 1);
      buckets[size_t(b)].emplace_back(v, o);
      lowest = std::min(lowest, b);
    }
  };
  Progress* progress = current_progress();
  size_t visited = 0, reported = 0;
  for (uint32_t seed : by_height) {
    if (done[seed]) continue;
    const bool away = sensor ? glm::dot(glm::dvec3(normals[seed]), *sensor - pts.origin - glm::dvec3(pts.points[seed])) < 0.0
                             : normals[seed].z < 0.0f;
    if (away) normals[seed] = -normals[seed];
    visit(seed);
    ++visited;
    while (true) {
      while (lowest < kBuckets && buckets[size_t(lowest)].empty()) ++lowest;
      if (lowest == kBuckets) break;
      const auto [from, to] = buckets[size_t(lowest)].back();
      buckets[size_t(lowest)].pop_back();
      if (done[to]) continue;
      if (glm::dot(normals[from], normals[to]) < 0.0f) normals[to] = -normals[to];
      visit(to);
      if (++visited - reported >= 16384) {
        check_cancelled(progress);
        advance(progress, visited - reported);
        reported = visited;
      }
    }
  }
  advance(progress, visited - reported);
}

}  // namespace pointnpr::geometry
