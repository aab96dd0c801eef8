#pragma once
// Per-point descriptors built on neighbourhoods: local resolution (seed 004),
// feature degree and line fit (seed 001), statistical outlier removal.
#include <optional>
#include <vector>

#include "geometry/local_points.h"
#include "geometry/neighbors.h"
#include "geometry/normals.h"

namespace pointnpr::geometry {

// Seed 004: r = mean distance to the k nearest other points, eps = standard
// deviation of those distances. nb must hold k+1 neighbours (the point
// itself first). Duplicates count as neighbours at distance 0; a lone point
// has r = eps = 0. LocalPoints order.
struct LocalResolution {
  std::vector<float> r, eps;
};
LocalResolution local_resolution(const Neighborhoods& nb_with_self);

// Seed 001 section 5.2, on points instead of scan images: the geometric
// part is the variation (standard deviation over the kNN neighbourhood) of
// the normal-estimation error (surface variation, pca.curvature); the colour
// part the same variation of luminance. Each is divided by its 99th
// percentile and clamped to [0,1]; the result is (1-w)*geometric +
// w*colour. Without colours (empty), w is ignored. A cloud whose parts do
// not vary has feature degree 0 everywhere. LocalPoints order.
std::vector<float> feature_degree(const Neighborhoods& nb, const std::vector<float>& curvature,
                                  const std::vector<uint32_t>& colors_rgba8, float color_weight);

// Seed 001 eq. 2 on the points with mask[i] (all points if mask is empty):
// the least-squares line through each masked point's k nearest masked
// points. direction: unit, largest-eigenvalue eigenvector; error:
// (l0+l1)/(l0+l1+l2) in [0, 2/3] (0 = a perfect line). Unmasked points and
// neighbourhoods whose points coincide get direction (0,0,0), error 1
// (non-directional). Original order in, original order out.
struct LineFit {
  std::vector<glm::vec3> direction;
  std::vector<float> error;
};
LineFit line_fit(const LocalPoints& pts, const std::vector<uint8_t>& mask_original, int k);

// PCL/Open3D statistical outlier removal: d_i = mean distance to the k
// nearest other points; a point is an inlier when d_i <= mean(d) +
// std_ratio * stddev(d). Returns 1 for inliers (LocalPoints order).
std::vector<uint8_t> inlier_mask(const Neighborhoods& nb_with_self, float std_ratio);

}  // namespace pointnpr::geometry
