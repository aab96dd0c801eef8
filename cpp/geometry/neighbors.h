#pragma once
// Neighbourhoods: a nanoflann k-d tree on the float offsets of LocalPoints,
// all-points kNN (parallel, TBB) and radius search.
#include <memory>
#include <utility>
#include <vector>

#include "geometry/local_points.h"

namespace pointnpr::geometry {

// The k nearest neighbours of every point, flat (N*k), nearest first. A point
// is its own first neighbour (or a duplicate of it is: both are at distance
// 0). k is min(requested k, N): fewer points than k gives every point all of
// them.
struct Neighborhoods {
  int k = 0;
  std::vector<uint32_t> index;  // indices into LocalPoints (Morton order)
  std::vector<float> dist2;     // squared distances
  const uint32_t* at(size_t i) const { return index.data() + i * size_t(k); }
  const float* d2_at(size_t i) const { return dist2.data() + i * size_t(k); }
};

class KdTree {
 public:
  explicit KdTree(const std::vector<glm::vec3>& points);  // keeps a reference
  ~KdTree();
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;
  // Up to k nearest (fewer when the tree has fewer points); returns the count.
  size_t knn(const glm::vec3& q, size_t k, uint32_t* index, float* dist2) const;
  // All points within radius (inclusive), nearest first.
  std::vector<std::pair<uint32_t, float>> radius(const glm::vec3& q, float radius) const;
  size_t size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

Neighborhoods knn_all(const KdTree& tree, const std::vector<glm::vec3>& points, int k);
// Only the first k of every row (k <= nb.k).
Neighborhoods truncate(const Neighborhoods& nb, int k);

}  // namespace pointnpr::geometry
