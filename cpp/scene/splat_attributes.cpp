#include "scene/splat_attributes.h"

#include "geometry/analysis.h"
#include "scene/gaussian_splats.h"
#include "scene/point_cloud.h"

namespace pointnpr {

std::vector<float> splat_radii(const PointCloud& cloud, int k) {
  const GaussianSplats* splats = cloud.gaussians();
  if (!splats) return cloud.analysis().surface_resolution(k)->r;
  std::vector<float> r(splats->scales.size());
  for (size_t i = 0; i < r.size(); ++i) r[i] = splat_radius(*splats, i);
  return r;
}

std::shared_ptr<const std::vector<float>> shared_splat_radii(const PointCloud& cloud, int k) {
  if (cloud.gaussians()) return std::make_shared<const std::vector<float>>(splat_radii(cloud, k));
  // Aliasing: the radii live as long as the cached LocalResolution they are part of.
  const std::shared_ptr<const geometry::LocalResolution> resolution = cloud.analysis().surface_resolution(k);
  return {resolution, &resolution->r};
}

std::vector<float> splat_opacities(const PointCloud& cloud) {
  const GaussianSplats* splats = cloud.gaussians();
  return splats ? splats->opacity : std::vector<float>(cloud.size(), 1.0f);
}

}  // namespace pointnpr
