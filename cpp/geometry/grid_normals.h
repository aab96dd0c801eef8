#pragma once
// Normals of a structured scan (an E57 scan's rowIndex/columnIndex grid)
// from its grid neighbours: no neighbour search, and oriented towards the
// scanner, which a k-nearest-neighbour estimate can only guess.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pointnpr::geometry {

// positions: n x 3; rows, columns: n grid indices; scanner: the scanner's
// position in the positions' frame (an E57 scan's pose translation). Per
// point, the cross product of the differences to its nearer column and row
// neighbour (the nearer one of each pair, so that a depth edge does not
// tilt the normal), unit length, turned to face the scanner. A point
// without a neighbour along a grid direction, or whose differences are
// parallel, faces the scanner (unit (scanner - p); (0, 0, 1) at the
// scanner). Returns n x 3 floats. Duplicate grid cells: the last point of
// a cell is the neighbour of the others.
std::vector<float> grid_normals(const double* positions, size_t n, const int64_t* rows, const int64_t* columns,
                                const double scanner[3]);

}  // namespace pointnpr::geometry
