#include "geometry/normals.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>
#include <queue>

namespace pointnpr::geometry {

PcaResult pca(const LocalPoints& pts, const Neighborhoods& nb) {
  const size_t n = pts.size();
  PcaResult r;
  r.normal.resize(n);
  r.curvature.resize(n);
  r.major.resize(n);
  r.linear_error.resize(n);
  r.degenerate.assign(n, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const uint32_t* idx = nb.at(i);
      const int k = nb.k;
      // Offsets from the point itself keep the sums small (two-pass).
      const glm::vec3 p0 = pts.points[i];
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int j = 0; j < k; ++j) {
        const glm::vec3 d = pts.points[idx[j]] - p0;
        mean += Eigen::Vector3d(d.x, d.y, d.z);
      }
      mean /= double(std::max(k, 1));
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (int j = 0; j < k; ++j) {
        const glm::vec3 d = pts.points[idx[j]] - p0;
        const Eigen::Vector3d e = Eigen::Vector3d(d.x, d.y, d.z) - mean;
        cov.noalias() += e * e.transpose();
      }
      const double trace = cov.trace();
      if (!(trace > 0.0)) {
        r.normal[i] = glm::vec3(0, 0, 1);
        r.major[i] = glm::vec3(1, 0, 0);
        r.curvature[i] = 0.0f;
        r.linear_error[i] = 0.0f;
        r.degenerate[i] = 1;
        continue;
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov / trace, Eigen::ComputeEigenvectors);
      Eigen::Vector3d l = es.eigenvalues().cwiseMax(0.0);
      const double sum = std::max(l.sum(), 1e-300);
      const Eigen::Vector3d v0 = es.eigenvectors().col(0).normalized();
      const Eigen::Vector3d v2 = es.eigenvectors().col(2).normalized();
      r.normal[i] = glm::vec3(float(v0.x()), float(v0.y()), float(v0.z()));
      r.major[i] = glm::vec3(float(v2.x()), float(v2.y()), float(v2.z()));
      r.curvature[i] = float(l[0] / sum);
      r.linear_error[i] = float((l[0] + l[1]) / sum);
    }
  });
  return r;
}

void orient(const LocalPoints& pts, const Neighborhoods& nb, std::vector<glm::vec3>& normals, Orientation how,
            const glm::dvec3& target) {
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
  const int k = nb.k;
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
  struct Edge {
    float w;
    uint32_t from, to;
    bool operator<(const Edge& o) const { return w > o.w || (w == o.w && to > o.to); }  // min-heap
  };
  std::priority_queue<Edge> heap;
  auto visit = [&](uint32_t v) {
    done[v] = 1;
    for (uint32_t e = start[v]; e < start[v + 1]; ++e) {
      const uint32_t o = adj[e];
      if (!done[o]) heap.push({1.0f - std::abs(glm::dot(normals[v], normals[o])), v, o});
    }
  };
  for (uint32_t seed : by_height) {
    if (done[seed]) continue;
    if (normals[seed].z < 0.0f) normals[seed] = -normals[seed];
    visit(seed);
    while (!heap.empty()) {
      const Edge e = heap.top();
      heap.pop();
      if (done[e.to]) continue;
      if (glm::dot(normals[e.from], normals[e.to]) < 0.0f) normals[e.to] = -normals[e.to];
      visit(e.to);
    }
  }
}

}  // namespace pointnpr::geometry
