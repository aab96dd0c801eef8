#include "geometry/analysis.h"

#include <algorithm>

#include "core/error.h"
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

Analysis::Analysis(const PointCloud& cloud) : cloud_(&cloud) {}
Analysis::Analysis(std::vector<double> xyz, std::vector<uint32_t> colors)
    : xyz_(std::move(xyz)), colors_(std::move(colors)) {
  if (xyz_.size() % 3 != 0) throw Error("positions must be an N x 3 array");
  if (!colors_.empty() && colors_.size() != xyz_.size() / 3) throw Error("colors must have one row per point");
}

size_t Analysis::size() const { return cloud_ ? cloud_->size() : xyz_.size() / 3; }

std::vector<double> Analysis::positions() const { return cloud_ ? cloud_->positions_double() : xyz_; }

template <class T>
std::shared_ptr<const T> Analysis::cached(const std::string& key) const {
  auto it = cache_.find(key);
  return it == cache_.end() ? nullptr : std::static_pointer_cast<const T>(it->second);
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

const std::vector<uint32_t>& Analysis::colors_sorted() {
  std::lock_guard lock(mutex_);
  if (!colors_sorted_) {
    const std::vector<uint32_t>& c = cloud_ ? cloud_->colors() : colors_;
    if (c.empty()) throw Error("the point set has no colours");
    colors_sorted_ = std::make_unique<std::vector<uint32_t>>(points().to_sorted(std::span<const uint32_t>(c)));
  }
  return *colors_sorted_;
}

std::shared_ptr<const Neighborhoods> Analysis::knn(int k) {
  check_k(k);
  std::lock_guard lock(mutex_);
  k = int(std::min<size_t>(size_t(k), std::max<size_t>(size(), 1)));
  const std::string key = "knn:" + std::to_string(k);
  if (auto hit = cached<Neighborhoods>(key)) return hit;
  // A larger cached k serves a smaller one (rows are sorted by distance).
  std::shared_ptr<const Neighborhoods> larger;
  for (const auto& [name, value] : cache_)
    if (name.rfind("knn:", 0) == 0) {
      auto nb = std::static_pointer_cast<const Neighborhoods>(value);
      if (nb->k >= k && (!larger || nb->k < larger->k)) larger = nb;
    }
  auto nb = larger ? std::make_shared<const Neighborhoods>(truncate(*larger, k))
                   : std::make_shared<const Neighborhoods>(knn_all(points(), k));
  cache_[key] = nb;
  return nb;
}

std::shared_ptr<const PcaResult> Analysis::pca(int k) {
  check_k(k);
  std::lock_guard lock(mutex_);
  k = int(std::min<size_t>(size_t(k), std::max<size_t>(size(), 1)));
  const std::string key = "pca:" + std::to_string(k);
  if (auto hit = cached<PcaResult>(key)) return hit;
  auto r = std::make_shared<const PcaResult>(geometry::pca(points(), *knn(k)));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const std::vector<glm::vec3>> Analysis::normals(const NormalOptions& o) {
  check_k(o.k);
  std::lock_guard lock(mutex_);
  const int k = int(std::min<size_t>(size_t(o.k), std::max<size_t>(size(), 1)));
  std::string key = "normals:" + std::to_string(k) + ":" + orientation_name(o.orientation);
  if (o.orientation == Orientation::TowardPoint || o.orientation == Orientation::Direction) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ":%.17g,%.17g,%.17g", o.target.x, o.target.y, o.target.z);
    key += buf;
  }
  if (auto hit = cached<std::vector<glm::vec3>>(key)) return hit;
  std::vector<glm::vec3> n = pca(k)->normal;
  orient(points(), *knn(k), n, o.orientation, o.target);
  auto r = std::make_shared<const std::vector<glm::vec3>>(points().to_original(n));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const std::vector<float>> Analysis::curvature(int k) {
  check_k(k);
  std::lock_guard lock(mutex_);
  const std::string key = "curvature:" + std::to_string(k);
  if (auto hit = cached<std::vector<float>>(key)) return hit;
  auto r = std::make_shared<const std::vector<float>>(points().to_original(pca(k)->curvature));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const LocalResolution> Analysis::local_resolution(int k) {
  check_k(k);
  std::lock_guard lock(mutex_);
  const std::string key = "local_resolution:" + std::to_string(k);
  if (auto hit = cached<LocalResolution>(key)) return hit;
  LocalResolution lr = geometry::local_resolution(*knn(k + 1));
  lr.r = points().to_original(lr.r);
  lr.eps = points().to_original(lr.eps);
  auto r = std::make_shared<const LocalResolution>(std::move(lr));
  cache_[key] = r;
  return r;
}

std::shared_ptr<const std::vector<float>> Analysis::feature_degree(int k, float color_weight) {
  check_k(k);
  std::lock_guard lock(mutex_);
  const bool has_colors = cloud_ ? !cloud_->colors().empty() : !colors_.empty();
  const float w = has_colors ? color_weight : 0.0f;
  const std::string key = "feature_degree:" + std::to_string(k) + ":" + std::to_string(w);
  if (auto hit = cached<std::vector<float>>(key)) return hit;
  static const std::vector<uint32_t> none;
  const std::vector<uint32_t>& colors = w > 0.0f ? colors_sorted() : none;
  auto r = std::make_shared<const std::vector<float>>(
      points().to_original(geometry::feature_degree(*knn(k), pca(k)->curvature, colors, w)));
  cache_[key] = r;
  return r;
}

std::vector<uint8_t> Analysis::inliers(int k, float std_ratio) {
  check_k(k);
  if (!(std_ratio >= 0.0f)) throw Error("std_ratio must be >= 0");
  std::lock_guard lock(mutex_);
  return points().to_original(inlier_mask(*knn(k + 1), std_ratio));
}

LineFit Analysis::line_fit(const std::vector<uint8_t>& mask, int k) {
  check_k(k);
  std::lock_guard lock(mutex_);
  return geometry::line_fit(points(), mask, k);
}

Components Analysis::region_growing_rgb(const RegionGrowingParams& params) {
  check_k(params.k);
  std::lock_guard lock(mutex_);
  return geometry::region_growing_rgb(points(), *knn(params.k), colors_sorted(), params);
}

Components Analysis::connected_components(int level, uint32_t min_points, double cell_size, bool float32) {
  std::lock_guard lock(mutex_);
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
