#include "geometry/analysis.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/progress.h"
#include <tbb/parallel_for.h>
#include "scene/gaussian_splats.h"
#include "scene/point_cloud.h"

namespace pointnpr::geometry {

namespace {
const char* orientation_name(Orientation o) {
  switch (o) {
    case Orientation::None: return "none";
    case Orientation::TowardPoint: return "point";
    case Orientation::Direction: return "direction";
    case Orientation::Consistent: return "consistent";
  }
  return "?";
}
void check_k(int k) {
  if (k < 1) throw Error("k must be at least 1 (got " + std::to_string(k) + ")");
}
}  // namespace

// Holds the lock for one public call and counts the nesting, so that only
// the outermost call plans the work on the caller's Progress.
class Analysis::Call {
 public:
  explicit Call(Analysis& a) : lock_(a.mutex_), analysis_(a) { ++a.depth_; }
  ~Call() { --analysis_.depth_; }
  Call(const Call&) = delete;
  Call& operator=(const Call&) = delete;
  void plan(uint64_t units) const {
    if (analysis_.depth_ != 1) return;
    if (Progress* p = current_progress()) p->expect(units);
  }

 private:
  std::lock_guard<std::recursive_mutex> lock_;
  Analysis& analysis_;
};

Analysis::Analysis(const PointCloud& cloud) : cloud_(&cloud) {}
Analysis::Analysis(std::vector<double> xyz, std::vector<uint32_t> colors, std::vector<float> intensity)
    : xyz_(std::move(xyz)), colors_(std::move(colors)), intensity_(std::move(intensity)) {
  if (xyz_.size() % 3 != 0) throw Error("positions must be an N x 3 array");
  if (!colors_.empty() && colors_.size() != xyz_.size() / 3) throw Error("colors must have one row per point");
  if (!intensity_.empty() && intensity_.size() != xyz_.size() / 3)
    throw Error("intensity must have one value per point");
}

size_t Analysis::size() const { return cloud_ ? cloud_->size() : xyz_.size() / 3; }

std::vector<double> Analysis::positions() const { return cloud_ ? cloud_->positions_double() : xyz_; }

bool Analysis::has_colors() const { return cloud_ ? !cloud_->colors().empty() : !colors_.empty(); }
bool Analysis::has_intensity() const { return cloud_ ? !cloud_->intensity().empty() : !intensity_.empty(); }

int Analysis::clamp_k(int k) const { return int(std::min<size_t>(size_t(k), std::max<size_t>(size(), 1))); }

template <class T>
std::shared_ptr<const T> Analysis::cached(const std::string& key) const {
  auto it = cache_.find(key);
  return it == cache_.end() ? nullptr : std::static_pointer_cast<const T>(it->second);
}

std::shared_ptr<const Neighborhoods> Analysis::largest_knn() const {
  std::shared_ptr<const Neighborhoods> largest;
  for (const auto& [name, value] : cache_)
    if (name.rfind("knn:", 0) == 0) {
      auto nb = std::static_pointer_cast<const Neighborhoods>(value);
      if (!largest || nb->k > largest->k) largest = nb;
    }
  return largest;
}

uint64_t Analysis::knn_work(int k) const {
  const auto largest = largest_knn();
  return largest && largest->k >= clamp_k(k) ? 0 : size();
}

uint64_t Analysis::pca_work(int k) const {
  return cache_.count("pca:" + std::to_string(clamp_k(k))) ? 0 : knn_work(k) + size();
}

const LocalPoints& Analysis::points() {
  std::lock_guard lock(mutex_);
  if (!points_) {
    const std::vector<double> xyz = positions();
    points_ = std::make_unique<LocalPoints>(LocalPoints::from(xyz));
  }
  return *points_;
}

const KdTree& Analysis::tree() {
  std::lock_guard lock(mutex_);
  if (!tree_) tree_ = std::make_unique<KdTree>(points().points);
  return *tree_;
}

// A per-point attribute in LocalPoints order, made once.
template <class T>
const std::vector<T>& Analysis::sorted(std::unique_ptr<std::vector<T>>& slot, const std::vector<T>& input,
                                       const char* missing) {
  std::lock_guard lock(mutex_);
  if (!slot) {
    if (input.empty() && size() > 0) throw Error(missing);
    slot = std::make_unique<std::vector<T>>(points().to_sorted(std::span<const T>(input)));
  }
  return *slot;
}

const std::vector<uint32_t>& Analysis::colors_sorted() {
  return sorted(colors_sorted_, cloud_ ? cloud_->colors() : colors_, "the point set has no colours");
}

const std::vector<float>& Analysis::intensity_sorted() {
  return sorted(intensity_sorted_, cloud_ ? cloud_->intensity() : intensity_, "the point set has no intensity");
}

std::shared_ptr<const Neighborhoods> Analysis::knn(int k) {
  check_k(k);
  const Call call(*this);
  k = clamp_k(k);
  const std::string key = "knn:" + std::to_string(k);
  if (auto hit = cached<Neighborhoods>(key)) return hit;
  call.plan(knn_work(k));
  // A larger cached k serves a smaller one (rows are sorted by distance).
  auto largest = largest_knn();
  auto nb = largest && largest->k >= k ? std::make_shared<const Neighborhoods>(truncate(*largest, k))
                                       : std::make_shared<const Neighborhoods>(knn_all(points(), k));
  cache_[key] = nb;
  return nb;
}

std::shared_ptr<const PcaResult> Analysis::pca(int k) {
  check_k(k);
  const Call call(*this);
  k = clamp_k(k);
  const std::string key = "pca:" + std::to_string(k);
  if (auto hit = cached<PcaResult>(key)) return hit;
  call.plan(pca_work(k));
  auto r = std::make_shared<const PcaResult>(geometry::pca(points(), *knn(k)));
  cache_[key] = r;
  return r;
}

namespace {
// Each splat's shortest axis, in the analysis's sorted order.
std::vector<glm::vec3> splat_axes(const GaussianSplats& g, const LocalPoints& pts) {
  std::vector<glm::vec3> n(pts.size());
  tbb::parallel_for(size_t(0), pts.size(), [&](size_t s) { n[s] = splat_axis(g, pts.original[s], false); });
  return n;
}
}  // namespace

std::shared_ptr<const std::vector<glm::vec3>> Analysis::normals(const NormalOptions& o) {
  check_k(o.k);
  const Call call(*this);
  const int k = clamp_k(o.k);
  std::string key = "normals:" + std::to_string(k) + ":" + orientation_name(o.orientation);
  if (o.orientation == Orientation::TowardPoint || o.orientation == Orientation::Direction) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ":%.17g,%.17g,%.17g", o.target.x, o.target.y, o.target.z);
    key += buf;
  }
  if (o.radius_factor > 0.0) {
    char buf[48];
    std::snprintf(buf, sizeof buf, ":radius%.9g", o.radius_factor);
    key += buf;
  }
  if (auto hit = cached<std::vector<glm::vec3>>(key)) return hit;
  // 3D Gaussian splats carry their surface: each splat's shortest axis is
  // its normal (then oriented as any estimate), no neighbourhood fit.
  const GaussianSplats* splats = cloud_ ? cloud_->gaussians() : nullptr;
  call.plan((splats ? size() : pca_work(k)) + (o.orientation == Orientation::Consistent ? size() : 0) +
            (o.radius_factor > 0.0 && !splats ? knn_work(9) + 2 * size() : 0));
  std::vector<glm::vec3> n = splats ? splat_axes(*splats, points()) : pca(k)->normal;
  if (o.radius_factor > 0.0 && !splats) {
    // Least squares within radius_factor x r, per point (sorted order).
    const std::vector<float>& r = local_resolution(8)->r;  // input order
    const LocalPoints& pts = points();
    const KdTree& kd = tree();
    constexpr size_t kMaxNeighbors = 64;
    tbb::parallel_for(size_t(0), pts.size(), [&](size_t s) {
      const float radius = float(o.radius_factor) * r[pts.original[s]];
      if (!(radius > 0.0f)) return;
      const auto found = kd.radius(pts.points[s], radius);
      const size_t m = std::min(found.size(), kMaxNeighbors);
      if (m < 3) return;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (size_t j = 0; j < m; ++j) {
        const glm::vec3& q = pts.points[found[j].first];
        mean += Eigen::Vector3d(q.x, q.y, q.z);
      }
      mean /= double(m);
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (size_t j = 0; j < m; ++j) {
        const glm::vec3& q = pts.points[found[j].first];
        const Eigen::Vector3d d = Eigen::Vector3d(q.x, q.y, q.z) - mean;
        cov += d * d.transpose();
      }
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
      const Eigen::Vector3d v = es.eigenvectors().col(0);
      if (v.allFinite() && es.eigenvalues()(1) > 0.0) n[s] = glm::normalize(glm::vec3(float(v.x()), float(v.y()), float(v.z())));
    });
    advance(current_progress(), size());
  }
  orient(points(), *knn(k), n, o.orientation, o.target, cloud_ ? cloud_->sensor() : std::nullopt);
  auto r = std::make_shared<const std::vector<glm::vec3>>(points().to_original(n));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const LocalResolution> Analysis::surface_resolution(int k) {
  check_k(k);
  const Call call(*this);
  const std::string key = "surface_resolution:" + std::to_string(k);
  if (auto hit = cached<LocalResolution>(key)) return hit;
  call.plan(knn_work(k + 1) + 2 * size());
  const Neighborhoods& nb = *knn(k + 1);
  LocalResolution lr = geometry::surface_resolution(geometry::local_resolution(nb), nb);
  lr.r = points().to_original(lr.r);
  lr.eps = points().to_original(lr.eps);
  auto r = std::make_shared<const LocalResolution>(std::move(lr));
  cache_[key] = r;
  return r;
}

float Analysis::plane_deviation(int k) {
  check_k(k);
  const Call call(*this);
  k = clamp_k(k);
  const std::string key = "plane_deviation:" + std::to_string(k);
  if (auto hit = cached<float>(key)) return *hit;
  call.plan(pca_work(k) + size());
  auto r = std::make_shared<const float>(geometry::median_plane_deviation(points(), *knn(k), *pca(k)));
  cache_[key] = r;
  return *r;
}

std::shared_ptr<const std::vector<float>> Analysis::curvature(int k) {
  check_k(k);
  const Call call(*this);
  const std::string key = "curvature:" + std::to_string(k);
  if (auto hit = cached<std::vector<float>>(key)) return hit;
  call.plan(pca_work(k));
  auto r = std::make_shared<const std::vector<float>>(points().to_original(pca(k)->curvature));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const LocalResolution> Analysis::local_resolution(int k) {
  check_k(k);
  const Call call(*this);
  const std::string key = "local_resolution:" + std::to_string(k);
  if (auto hit = cached<LocalResolution>(key)) return hit;
  call.plan(knn_work(k + 1) + size());
  LocalResolution lr = geometry::local_resolution(*knn(k + 1));
  lr.r = points().to_original(lr.r);
  lr.eps = points().to_original(lr.eps);
  auto r = std::make_shared<const LocalResolution>(std::move(lr));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const std::vector<float>> Analysis::feature_degree(int k, const FeatureOptions& options) {
  check_k(k);
  const Call call(*this);
  const bool colors = has_colors(), intensity = has_intensity();
  FeatureOptions o = options;
  if (!colors && !intensity) o.edge_weight = 0.0f;  // nothing to detect edges on: the key says so
  char key[128];
  std::snprintf(key, sizeof key, "feature_degree:%d:%.9g:%.9g", k, double(o.edge_weight), double(o.contrast));
  if (auto hit = cached<std::vector<float>>(key)) return hit;
  call.plan(pca_work(k) + size());
  static const std::vector<uint32_t> no_colors;
  static const std::vector<float> no_intensity;
  const bool edges = o.edge_weight > 0.0f;
  auto r = std::make_shared<const std::vector<float>>(points().to_original(geometry::feature_degree(
      points(), *knn(k), *pca(k), edges && colors ? colors_sorted() : no_colors,
      edges && intensity ? intensity_sorted() : no_intensity, o)));
  cache_[key] = r;
  return r;
}

std::vector<uint8_t> Analysis::inliers(int k, float std_ratio) {
  check_k(k);
  if (!(std_ratio >= 0.0f)) throw Error("std_ratio must be >= 0");
  const Call call(*this);
  call.plan(knn_work(k + 1) + size());
  return points().to_original(inlier_mask(*knn(k + 1), std_ratio));
}

LineFit Analysis::line_fit(const std::vector<uint8_t>& mask, int k) {
  check_k(k);
  const Call call(*this);
  call.plan(2 * size());
  return geometry::line_fit(points(), mask, k);
}

Components Analysis::region_growing_rgb(const RegionGrowingParams& params) {
  check_k(params.k);
  if (params.region_neighbours < 0) throw Error("region_neighbours must be >= 0");
  const Call call(*this);
  const int k = std::max(params.k, params.region_neighbours);
  call.plan(knn_work(k) + 2 * size());
  return geometry::region_growing_rgb(points(), *knn(k), colors_sorted(), params);
}

std::shared_ptr<const ClusterShapes> Analysis::cluster_shapes(int k) {
  check_k(k);
  const Call call(*this);
  const std::string key = "cluster_shapes:" + std::to_string(k);
  if (auto hit = cached<ClusterShapes>(key)) return hit;
  const size_t n = size();
  ClusterShapes out;
  out.label.assign(n, -1);
  out.size.assign(n, 0);
  out.axis.assign(n, glm::vec3(0.0f));
  out.elongation.assign(n, 1.0f);
  if (has_colors() && n > 1) {
    call.plan(knn_work(std::max(k, 9)) + 3 * size());
    std::vector<float> r = local_resolution(8)->r;
    std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
    RegionGrowingParams params;
    params.k = clamp_k(k);
    params.distance_threshold = r[r.size() / 2] > 0.0f ? 3.0 * double(r[r.size() / 2]) : 0.05;
    const Components c = region_growing_rgb(params);
    // Moments per cluster in local (offset) coordinates, in sorted order.
    const LocalPoints& pts = points();
    std::vector<uint32_t> count(size_t(c.count), 0);
    std::vector<Eigen::Vector3d> sum(size_t(c.count), Eigen::Vector3d::Zero());
    std::vector<Eigen::Matrix3d> sq(size_t(c.count), Eigen::Matrix3d::Zero());
    for (size_t s = 0; s < n; ++s) {
      const int32_t l = c.labels[pts.original[s]];
      if (l < 0) continue;
      const Eigen::Vector3d q(pts.points[s].x, pts.points[s].y, pts.points[s].z);
      ++count[size_t(l)];
      sum[size_t(l)] += q;
      sq[size_t(l)] += q * q.transpose();
    }
    std::vector<glm::vec3> axis(size_t(c.count), glm::vec3(0.0f));
    std::vector<float> elongation(size_t(c.count), 1.0f);
    for (size_t l = 0; l < size_t(c.count); ++l) {
      if (count[l] < 3) continue;
      const Eigen::Vector3d mean = sum[l] / double(count[l]);
      const Eigen::Matrix3d cov = sq[l] / double(count[l]) - mean * mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
      const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending
      const Eigen::Vector3d major = es.eigenvectors().col(2);
      axis[l] = glm::normalize(glm::vec3(float(major.x()), float(major.y()), float(major.z())));
      elongation[l] = ev(1) > 0.0 ? float(std::min(std::sqrt(ev(2) / ev(1)), 1000.0)) : 1000.0f;
    }
    for (size_t i = 0; i < n; ++i) {
      const int32_t l = c.labels[i];
      if (l < 0) continue;
      out.label[i] = l;
      out.size[i] = count[size_t(l)];
      out.axis[i] = axis[size_t(l)];
      out.elongation[i] = elongation[size_t(l)];
    }
  }
  auto result = std::make_shared<const ClusterShapes>(std::move(out));
  cache_[key] = result;
  return result;
}

Components Analysis::connected_components(int level, uint32_t min_points, double cell_size, bool float32) {
  const Call call(*this);
  call.plan(3 * size());
  const std::vector<double> xyz = positions();
  return geometry::connected_components(xyz, level, min_points, cell_size, float32);
}

std::vector<std::string> Analysis::computed() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  if (points_) out.push_back("points");
  if (tree_) out.push_back("tree");
  for (const auto& [name, value] : cache_) out.push_back(name);
  return out;
}

}  // namespace pointnpr::geometry
