#pragma once
// Normals by PCA of the k nearest neighbours (seed 001 eq. 1, Hoppe et al.
// 1992): the eigenvector of the smallest eigenvalue of the neighbourhood's
// covariance, from Eigen's iterative SelfAdjointEigenSolver in double (the
// closed-form 3x3 solver loses precision on nearly planar and nearly
// isotropic neighbourhoods). Surface variation l0/(l0+l1+l2) comes with it.
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "geometry/local_points.h"
#include "geometry/neighbors.h"

namespace pointnpr::geometry {

// Per point, in LocalPoints (Morton) order.
struct PcaResult {
  std::vector<glm::vec3> normal;    // unit; sign as the solver gives it
  std::vector<float> curvature;     // surface variation in [0, 1/3]
  std::vector<glm::vec3> major;     // unit eigenvector of the largest eigenvalue
  std::vector<float> linear_error;  // (l0+l1)/(l0+l1+l2): 0 on a line (seed 001 eq. 2)
  std::vector<uint8_t> degenerate;  // 1 where all neighbours coincide
};

// Degenerate neighbourhoods (a single point, all points identical): normal
// (0,0,1), major (1,0,0), curvature 0, linear_error 0. Collinear points: a
// unit normal perpendicular to the line, curvature 0.
PcaResult pca(const LocalPoints& pts, const Neighborhoods& nb);

enum class Orientation {
  None,        // as the solver gives it
  TowardPoint, // n . (target - p) >= 0 (a scanner position or a viewpoint)
  Direction,   // n . target >= 0
  Consistent,  // propagated along a minimum spanning tree (see below)
};

// Orientation in place (normals in LocalPoints order). TowardPoint takes the
// target in the same (world) frame as the input positions. Consistent:
// Hoppe's propagation along a minimum spanning tree of the symmetric graph
// of the (at most 10) nearest neighbours weighted by 1-|ni.nj| (quantised to 1/1024), one tree per connected
// part, each started at
// its highest point (largest z) with its normal turned to +z, or where the
// scan knows its sensor (`sensor`, world frame), turned to face it: a depth
// camera looks along +z, so +z would turn its surfaces away.
void orient(const LocalPoints& pts, const Neighborhoods& nb, std::vector<glm::vec3>& normals,
            Orientation how, const glm::dvec3& target = glm::dvec3(0.0),
            const std::optional<glm::dvec3>& sensor = std::nullopt);

}  // namespace pointnpr::geometry
