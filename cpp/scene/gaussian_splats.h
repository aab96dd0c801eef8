#pragma once
// 3D Gaussian splats (Kerbl et al. 2023) carried by a PointCloud: each point
// is the mean of a Gaussian with its opacity, scales, rotation and
// spherical-harmonic colour, in the cloud's (Morton) order.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace pointnpr {

// SH basis constants of the 3DGS reference renderer (real SH, degree 0-3).
constexpr float kShC0 = 0.28209479177387814f;

struct GaussianSplats {
  std::vector<float> opacity;        // in [0, 1] (after the sigmoid)
  std::vector<glm::vec3> scales;     // standard deviations along the local axes, scene units (after exp)
  std::vector<glm::vec4> rotations;  // unit quaternions (w, x, y, z)
  // (sh_degree + 1)^2 coefficients per point, each r, g, b: point i,
  // coefficient k, channel c at sh[(i * coefficients + k) * 3 + c].
  std::vector<float> sh;
  int sh_degree = 0;
  int coefficients() const { return (sh_degree + 1) * (sh_degree + 1); }
};

}  // namespace pointnpr
