#pragma once
// 3D Gaussian splats (Kerbl et al. 2023) carried by a PointCloud: each point
// is the mean of a Gaussian with its opacity, scales, rotation and
// spherical-harmonic colour, in the cloud's (Morton) order.
#include <algorithm>
#include <cmath>
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
  // Trained with anti-aliasing (Mip-Splatting): each splat's opacity is
  // scaled by sqrt(det S / det(S + 0.3 I)) of its 2D covariance S.
  bool antialiased = false;
  int coefficients() const { return (sh_degree + 1) * (sh_degree + 1); }
};

// A splat's shortest (its normal) or longest axis: the column of its
// rotation with the smallest or largest scale, unit length (its sign is
// the rotation's: orient it where it matters).
inline glm::vec3 splat_axis(const GaussianSplats& g, size_t i, bool longest) {
  const glm::vec4 q = g.rotations[i];  // w, x, y, z
  const glm::vec3 s = g.scales[i];
  const int a = longest ? (s.x >= s.y && s.x >= s.z ? 0 : (s.y >= s.z ? 1 : 2))
                        : (s.x <= s.y && s.x <= s.z ? 0 : (s.y <= s.z ? 1 : 2));
  const float w = q.x, x = q.y, y = q.z, z = q.w;
  glm::vec3 c;
  if (a == 0) c = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
  else if (a == 1) c = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
  else c = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
  const float len = glm::length(c);
  return len > 0.0f ? c / len : (longest ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f));
}

// A splat's footprint for the marks that draw it as one disc (brush size,
// world-size points): 2 sqrt of the product of its two largest scales, the
// mean radius of the ellipse at 2 sigma in its own plane (86 % of its mass;
// the smallest scale is the surface's thickness, not its extent).
inline float splat_radius(const GaussianSplats& g, size_t i) {
  const glm::vec3 s = g.scales[i];
  const float lo = std::min(s.x, std::min(s.y, s.z));
  const float hi = std::max(s.x, std::max(s.y, s.z));
  const float mid = s.x + s.y + s.z - lo - hi;
  return 2.0f * std::sqrt(hi * mid);
}

// Every splat's shortest or longest axis, in the cloud's order.
inline std::vector<glm::vec3> splat_axes(const GaussianSplats& g, bool longest) {
  std::vector<glm::vec3> axes(g.scales.size());
  for (size_t i = 0; i < axes.size(); ++i) axes[i] = splat_axis(g, i, longest);
  return axes;
}

}  // namespace pointnpr
