// Normals of structured scans from their row/column grid (E57 scans).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/grid_normals.h"

namespace pointnpr::geometry {
namespace {

// A rows x columns grid on the plane z = height(x, y), one point per cell.
struct Grid {
  std::vector<double> positions;
  std::vector<int64_t> rows, columns;
};

template <class Height>
Grid make_grid(int64_t height, int64_t width, Height z) {
  Grid g;
  for (int64_t r = 0; r < height; ++r)
    for (int64_t c = 0; c < width; ++c) {
      const double x = 0.1 * static_cast<double>(c), y = 0.1 * static_cast<double>(r);
      g.positions.insert(g.positions.end(), {x, y, z(x, y)});
      g.rows.push_back(r + 1000);  // indices need not start at 0
      g.columns.push_back(c - 7);
    }
  return g;
}

TEST(GridNormals, APlaneFacesTheScannerOnEitherSide) {
  const Grid g = make_grid(6, 9, [](double x, double y) { return 0.5 * x + 0.25 * y; });
  const double n_expected[3] = {-0.5, -0.25, 1.0};
  const double len = std::sqrt(0.25 + 0.0625 + 1.0);
  for (double side : {1.0, -1.0}) {
    const double scanner[3] = {0.3, 0.2, side * 50.0};
    const std::vector<float> n = grid_normals(g.positions.data(), g.rows.size(), g.rows.data(), g.columns.data(), scanner);
    ASSERT_EQ(n.size(), g.positions.size());
    for (size_t i = 0; i < g.rows.size(); ++i)
      for (int a = 0; a < 3; ++a) ASSERT_NEAR(n[3 * i + a], side * n_expected[a] / len, 1e-6) << i;
  }
}

TEST(GridNormals, ADepthEdgeDoesNotTiltTheNormalsBesideIt) {
  // Two flat terraces (z = 0 for x < 0.45, z = 5 beyond): the nearer
  // neighbour keeps each edge point's normal vertical.
  const Grid g = make_grid(5, 10, [](double x, double) { return x < 0.45 ? 0.0 : 5.0; });
  const double scanner[3] = {0, 0, 100};
  const std::vector<float> n = grid_normals(g.positions.data(), g.rows.size(), g.rows.data(), g.columns.data(), scanner);
  for (size_t i = 0; i < g.rows.size(); ++i) EXPECT_NEAR(n[3 * i + 2], 1.0f, 1e-6) << i;
}

TEST(GridNormals, LonePointsFaceTheScannerAndSparseGridsWork) {
  // Far-apart indices (a hash map rather than a dense array) and no neighbours at all.
  const std::vector<double> p = {1, 0, 0, 0, 3, 0, 0, 0, 0};
  const std::vector<int64_t> rows = {0, int64_t{1} << 30, 5}, columns = {0, 7, -(int64_t{1} << 30)};
  const double scanner[3] = {0, 0, 0};
  const std::vector<float> n = grid_normals(p.data(), 3, rows.data(), columns.data(), scanner);
  const std::vector<float> expected = {-1, 0, 0, 0, -1, 0, 0, 0, 1};  // the last point is at the scanner
  EXPECT_EQ(n, expected);
}

}  // namespace
}  // namespace pointnpr::geometry
