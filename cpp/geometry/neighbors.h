#pragma once
// Neighbourhoods on the float offsets of LocalPoints: the exact kNN of all
// points on their Morton grid (parallel, TBB), and a nanoflann k-d tree for
// radius search and the kNN of single points.
#include <memory>
#include <utility>
#include <vector>

#include "geometry/local_points.h"

namespace pointnpr::geometry {

// The k nearest neighbours of every point, flat (N*k), nearest first. "The
// k nearest" is one well-defined set: the k smallest by (float squared
// distance, index), so ties go to the lower index and every search path
// gives the same bytes. A point is its own first neighbour, or a duplicate
// of it with a lower index is (both are at distance 0). k is min(requested
// k, N): fewer points than k gives every point all of them.
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
  // The k nearest by (squared distance, index), nearest first (fewer when
  // the tree has fewer points); returns the count.
  size_t knn(const glm::vec3& q, size_t k, uint32_t* index, float* dist2) const;
  // All points within radius (inclusive), nearest first.
  std::vector<std::pair<uint32_t, float>> radius(const glm::vec3& q, float radius) const;
  size_t size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The kNN of every point (exact; on the Morton grid of LocalPoints, see
// neighbors.cpp).
Neighborhoods knn_all(const LocalPoints& points, int k);
// Only the first k of every row (k <= nb.k).
Neighborhoods truncate(const Neighborhoods& nb, int k);

}  // namespace pointnpr::geometry
