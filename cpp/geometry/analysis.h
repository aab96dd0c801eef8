#pragma once
// Lazy, cached geometry of one point set. Nothing is computed until asked;
// each result (neighbourhoods per k, PCA per k, normals per k and
// orientation, ...) is computed once and kept. A PointCloud owns one
// (PointCloud::analysis()); its points never change, so the cache never
// needs invalidating: a changed cloud is a new PointCloud with a new cache.
// Results are in the order of the input positions (for a PointCloud, its
// internal order, the order of point_index()). Thread-safe.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "geometry/features.h"
#include "geometry/local_points.h"
#include "geometry/neighbors.h"
#include "geometry/normals.h"
#include "geometry/segmentation.h"

namespace pointnpr {
class PointCloud;
}

namespace pointnpr::geometry {

// Seed 004 section 3.2.1: colour region-growing clusters and their shape,
// per point (input order). Region growing (PCL RegionGrowingRGB, colour
// thresholds 6 and 5, clusters of at least 10 points) over k neighbours,
// distance threshold 3 x the median local resolution (8 neighbours), so it
// holds at any scene scale. A cloud without colours has no clusters.
struct ClusterShapes {
  std::vector<int32_t> label;     // -1: in no cluster
  std::vector<uint32_t> size;     // points of the point's cluster (0: none)
  std::vector<glm::vec3> axis;    // unit main axis of the cluster (largest principal component; 0: none)
  std::vector<float> elongation;  // sqrt(l1 / l2) of the cluster's covariance (1: round or none)
};

struct NormalOptions {
  int k = 16;
  Orientation orientation = Orientation::Consistent;
  glm::dvec3 target{0.0};  // the point (TowardPoint) or direction (Direction)
  // > 0: the least-squares plane of the points within radius_factor x r
  // (r: the point's mean distance to its 8 nearest neighbours; seed 004
  // uses 3r), at most the 64 nearest of them; fewer than 3 there: the k
  // neighbours' plane. Orientation still follows the k-neighbour graph.
  double radius_factor = 0.0;
};

class Analysis {
 public:
  explicit Analysis(const PointCloud& cloud);  // reads the cloud lazily; must not outlive it
  explicit Analysis(std::vector<double> xyz, std::vector<uint32_t> colors_rgba8 = {},
                    std::vector<float> intensity = {});
  Analysis(const Analysis&) = delete;
  Analysis& operator=(const Analysis&) = delete;

  // Every call below reports to the Progress of the calling thread's
  // ProgressScope, if any (the outermost call plans the work of what is not
  // cached yet), and throws Cancelled once it is cancelled.
  size_t size() const;
  const LocalPoints& points();
  const KdTree& tree();
  std::shared_ptr<const Neighborhoods> knn(int k);
  std::shared_ptr<const PcaResult> pca(int k);

  // Input order. k is clamped to the number of points.
  std::shared_ptr<const std::vector<glm::vec3>> normals(const NormalOptions& options);
  std::shared_ptr<const std::vector<float>> curvature(int k);
  std::shared_ptr<const LocalResolution> local_resolution(int k);
  // local_resolution with outliers' r capped by their neighbours'
  // (geometry::surface_resolution): what marks size their marks from.
  std::shared_ptr<const LocalResolution> surface_resolution(int k);
  // The scan's depth noise over k neighbours (geometry::median_plane_deviation).
  float plane_deviation(int k);
  std::shared_ptr<const std::vector<float>> feature_degree(int k, const FeatureOptions& options);
  std::vector<uint8_t> inliers(int k, float std_ratio);
  LineFit line_fit(const std::vector<uint8_t>& mask, int k);
  Components region_growing_rgb(const RegionGrowingParams& params);
  std::shared_ptr<const ClusterShapes> cluster_shapes(int k);
  Components connected_components(int level, uint32_t min_points, double cell_size = 0.0, bool float32 = false);

  // What has been computed so far ("knn:16", "pca:16", "normals:16:consistent", ...).
  std::vector<std::string> computed() const;

 private:
  std::vector<double> positions() const;
  const std::vector<uint32_t>& colors_sorted();
  const std::vector<float>& intensity_sorted();
  template <class T>
  const std::vector<T>& sorted(std::unique_ptr<std::vector<T>>& slot, const std::vector<T>& input,
                               const char* missing);
  bool has_colors() const;
  bool has_intensity() const;
  int clamp_k(int k) const;
  template <class T>
  std::shared_ptr<const T> cached(const std::string& key) const;
  std::shared_ptr<const Neighborhoods> largest_knn() const;
  // Work (points per pass) still to do for a kNN / PCA of k: 0 when cached.
  uint64_t knn_work(int k) const;
  uint64_t pca_work(int k) const;
  // Plans `units` of work on the calling thread's Progress if this is the
  // outermost call (nested calls are part of the outer call's plan).
  class Call;

  mutable std::recursive_mutex mutex_;
  int depth_ = 0;  // nesting of public calls (under mutex_)
  const PointCloud* cloud_ = nullptr;
  std::vector<double> xyz_;
  std::vector<uint32_t> colors_;  // input order
  std::vector<float> intensity_;  // input order
  std::unique_ptr<LocalPoints> points_;
  std::unique_ptr<KdTree> tree_;
  std::unique_ptr<std::vector<uint32_t>> colors_sorted_;
  std::unique_ptr<std::vector<float>> intensity_sorted_;
  std::map<std::string, std::shared_ptr<const void>> cache_;
};

}  // namespace pointnpr::geometry
