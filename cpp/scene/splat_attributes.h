#pragma once
// The Gaussian-splat attributes that other marks read (render/attributes.h
// SplatRadius, SplatOpacity), in the cloud's order, for the GPU cache and
// the native passes alike; plain points get the values that leave a mark
// as it draws them without splats.
#include <memory>
#include <vector>

namespace pointnpr {

class PointCloud;

// Each splat's footprint radius (scene/gaussian_splats.h splat_radius);
// plain points: the mean distance to their k nearest neighbours.
std::vector<float> splat_radii(const PointCloud& cloud, int k);
// The same, shared: plain points' are the cloud's cached neighbour
// distances (no copy per frame), a capture's made once per call.
std::shared_ptr<const std::vector<float>> shared_splat_radii(const PointCloud& cloud, int k);
// Each splat's opacity; plain points: 1.
std::vector<float> splat_opacities(const PointCloud& cloud);

}  // namespace pointnpr
