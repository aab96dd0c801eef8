#pragma once
// Per-point descriptors built on neighbourhoods: local resolution (seed 004),
// feature degree and line fit (seed 001), statistical outlier removal.
#include <array>
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
  // The median of r: the scan's own spacing, what marks size their
  // surface from (0 where it is not positive and finite).
  float median_r = 0.0f;
  // The 90th percentile of r: the spacing nine in ten points have at most,
  // what a gap between neighbouring samples of the scan (not a hole in it)
  // stays within also where the scan is sparser than its median (an
  // aerial tile's single flight lines, a range scan's far side).
  float sparse_r = 0.0f;
};
LocalResolution local_resolution(const Neighborhoods& nb_with_self);
// What marks size their surface from: `raw` (local_resolution of the same
// neighbourhoods, in their order) with each point's r capped at twice the
// median r of its neighbours, and eps scaled alike. A point far from the
// surface it belongs to (an outlier, a stray point in the sky) has a large
// r of its own while its neighbours, on that surface, have small ones: its
// marks stay the size of its neighbourhood's instead of spanning the gap.
// Surface points (r near their neighbours') keep theirs; median_r is raw's.
LocalResolution surface_resolution(const LocalResolution& raw, const Neighborhoods& nb_with_self);

// The scan's own depth noise: the median over its points of the RMS
// distance of a point's neighbours from the plane through it (its PCA
// normal): about sigma for noise of sigma along the normal (measured
// 1.07 sigma with 15 neighbours; test_geometry.cpp), so a test of "on the
// same surface" must allow a few times it. 0 for fewer than 3 points.
// LocalPoints order for pca and nb.
float median_plane_deviation(const LocalPoints& pts, const Neighborhoods& nb_with_self, const PcaResult& pca);

// Seed 001 section 5.2, on points instead of scan images. Geometric part:
// the variation (standard deviation over the kNN neighbourhood) of the
// normal-estimation error (the plane fit's surface variation,
// pca.curvature), divided by its 99th percentile and clamped to [0, 1].
// Edge part, where the points have colours or intensity: the seed's "edge
// detection filter on the color or intensity image", as a point-space edge
// detector (edge_strength below) on CIELAB colours and on intensity as a
// lightness (0-100 at its 99th percentile), the stronger of the two,
// divided by `contrast` (or by five times its median over the cloud, where
// that is larger: a textured scan's colours vary everywhere) and clamped
// to [0, 1]. Result: (1 - w) * geometric
// + w * edge (w = edge_weight; the geometric part alone without colours and
// intensity). A cloud whose parts do not vary has feature degree 0
// everywhere. LocalPoints order; colors/intensity in that order or empty.
struct FeatureOptions {
  float edge_weight = 0.5f;
  float contrast = 25.0f;  // colour difference (Delta E 1976) at which the edge part saturates
};
std::vector<float> feature_degree(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                                  const std::vector<uint32_t>& colors_rgba8, const std::vector<float>& intensity,
                                  const FeatureOptions& options);

// A point-space edge detector for a field of C channels per point: the
// least-squares gradient of each channel over the neighbourhood, in its
// tangent plane, combined by Di Zenzo's structure tensor (the square root
// of its largest eigenvalue), times 2x the RMS tangent offset of the
// neighbourhood: the field's change across the neighbourhood, in the
// field's units. A step of height D through a uniformly sampled disc gives
// 8/(3 pi) D = 0.85 D; a uniform field gives 0. Degenerate neighbourhoods: 0.
template <int C>
std::vector<float> edge_strength(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                                 const std::vector<std::array<float, C>>& field);
// On sRGB colours in CIELAB (Delta E), and on intensity as a lightness.
std::vector<float> color_edges(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                               const std::vector<uint32_t>& colors_rgba8);
std::vector<float> intensity_edges(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                                   const std::vector<float>& intensity);

// Seed 001 eq. 2 on the points with mask[i] (all points if mask is empty):
// the least-squares line through each masked point's k nearest masked
// points. direction: unit, largest-eigenvalue eigenvector; error:
// (l0+l1)/(l0+l1+l2) in [0, 2/3] (0 = a perfect line). Unmasked points and
// neighbourhoods whose points coincide get direction (0,0,0), error 1
// (non-directional). Original order in, original order out. The masked
// points' chains (geometry/feature_chains.h) over the same neighbourhoods:
// to_parent (0: none) and chain_end.
struct LineFit {
  std::vector<glm::vec3> direction;
  std::vector<float> error;
  std::vector<glm::vec3> to_parent;
  std::vector<uint8_t> chain_end;
};
LineFit line_fit(const LocalPoints& pts, const std::vector<uint8_t>& mask_original, int k);

// PCL/Open3D statistical outlier removal: d_i = mean distance to the k
// nearest other points; a point is an inlier when d_i <= mean(d) +
// std_ratio * stddev(d). Returns 1 for inliers (LocalPoints order).
std::vector<uint8_t> inlier_mask(const Neighborhoods& nb_with_self, float std_ratio);

// The 99th percentile (0 for no values): a scale that a few extreme values
// (glints, outliers) do not set.
float percentile99(std::vector<float> values);

}  // namespace pointnpr::geometry
