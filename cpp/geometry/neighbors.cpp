#include "geometry/neighbors.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>

#include "core/error.h"

namespace pointnpr::geometry {

namespace {
struct Adaptor {
  const std::vector<glm::vec3>* pts;
  size_t kdtree_get_point_count() const { return pts->size(); }
  float kdtree_get_pt(size_t i, size_t d) const { return (*pts)[i][int(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor, float, uint32_t>,
                                                 Adaptor, 3, uint32_t>;
}  // namespace

struct KdTree::Impl {
  Adaptor adaptor;
  Tree tree;
  explicit Impl(const std::vector<glm::vec3>& p)
      : adaptor{&p}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(20)) {}
};

KdTree::KdTree(const std::vector<glm::vec3>& points) : impl_(std::make_unique<Impl>(points)) {}
KdTree::~KdTree() = default;
size_t KdTree::size() const { return impl_->adaptor.pts->size(); }

size_t KdTree::knn(const glm::vec3& q, size_t k, uint32_t* index, float* dist2) const {
  if (size() == 0 || k == 0) return 0;
  return impl_->tree.knnSearch(&q.x, k, index, dist2);
}

std::vector<std::pair<uint32_t, float>> KdTree::radius(const glm::vec3& q, float r) const {
  std::vector<std::pair<uint32_t, float>> out;
  if (size() == 0 || !(r >= 0.0f)) return out;
  // nanoflann compares squared distances strictly: nudge to include r itself.
  impl_->tree.radiusSearch(&q.x, std::nextafter(r * r, std::numeric_limits<float>::max()), out,
                           nanoflann::SearchParams(32, 0.0f, true));
  return out;
}

Neighborhoods knn_all(const KdTree& tree, const std::vector<glm::vec3>& points, int k) {
  if (k < 1) throw Error("k must be at least 1");
  Neighborhoods nb;
  const size_t n = points.size();
  nb.k = int(std::min<size_t>(size_t(k), tree.size()));
  if (n == 0) return nb;
  nb.index.resize(n * size_t(nb.k));
  nb.dist2.resize(n * size_t(nb.k));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const size_t got = tree.knn(points[i], size_t(nb.k), nb.index.data() + i * nb.k, nb.dist2.data() + i * nb.k);
      // Cannot happen (the tree holds these points), but never leave garbage.
      for (size_t j = got; j < size_t(nb.k); ++j) {
        nb.index[i * nb.k + j] = uint32_t(i);
        nb.dist2[i * nb.k + j] = 0.0f;
      }
    }
  });
  return nb;
}

Neighborhoods truncate(const Neighborhoods& nb, int k) {
  if (k >= nb.k) return nb;
  Neighborhoods out;
  out.k = k;
  const size_t n = nb.k ? nb.index.size() / size_t(nb.k) : 0;
  out.index.resize(n * size_t(k));
  out.dist2.resize(n * size_t(k));
  for (size_t i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      out.index[i * k + j] = nb.index[i * nb.k + j];
      out.dist2[i * k + j] = nb.dist2[i * nb.k + j];
    }
  return out;
}

}  // namespace pointnpr::geometry
