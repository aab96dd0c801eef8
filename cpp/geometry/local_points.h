#pragma once
// Points as the geometry layer sees them: float offsets from a double local
// origin (the bounding-box centre), so that a georeferenced scan at 1e6 m
// gives the same neighbourhoods and normals as the same scan at the origin;
// stored in Morton (Z-order) so that neighbours are close in memory.
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace pointnpr::geometry {

struct LocalPoints {
  glm::dvec3 origin{0.0};
  std::vector<glm::vec3> points;    // Morton order, offsets from origin
  std::vector<uint32_t> original;   // original index of each sorted point
  // The Morton grid: 2^21 cells per axis over the bounding box's largest
  // extent; cell coordinates of a point = (world - grid_min) * grid_scale.
  // code[s] is the (sorted) Morton code of points[s]; identical points are
  // adjacent (ties in code are ordered by position, then index).
  std::vector<uint64_t> code;
  glm::dvec3 grid_min{0.0};
  double grid_scale = 1.0;
  size_t size() const { return points.size(); }

  // xyz: N*3 doubles. Throws Error on non-finite coordinates or N >= 2^31.
  static LocalPoints from(std::span<const double> xyz);

  // out[original[s]] = in[s]: results computed in Morton order, returned in
  // the caller's order.
  template <class T>
  std::vector<T> to_original(const std::vector<T>& sorted) const {
    std::vector<T> out(sorted.size());
    for (size_t s = 0; s < sorted.size(); ++s) out[original[s]] = sorted[s];
    return out;
  }
  template <class T>
  std::vector<T> to_sorted(std::span<const T> in_original) const {
    std::vector<T> out(size());
    for (size_t s = 0; s < size(); ++s) out[s] = in_original[original[s]];
    return out;
  }
};

}  // namespace pointnpr::geometry
