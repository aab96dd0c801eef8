#include "geometry/grid_normals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"

namespace pointnpr::geometry {

namespace {

constexpr uint32_t kEmpty = std::numeric_limits<uint32_t>::max();

// Point index by grid cell: a dense array when the grid's bounding box is
// not much larger than the point count, a hash map otherwise.
class GridIndex {
 public:
  GridIndex(const int64_t* rows, const int64_t* columns, size_t n) {
    row0_ = *std::min_element(rows, rows + n), col0_ = *std::min_element(columns, columns + n);
    const uint64_t height = static_cast<uint64_t>(*std::max_element(rows, rows + n) - row0_) + 1;
    width_ = static_cast<uint64_t>(*std::max_element(columns, columns + n) - col0_) + 1;
    dense_ = height <= (4 * n + 1024) / width_ && width_ <= 4 * n + 1024;
    if (dense_) cells_.assign(height * width_, kEmpty);
    else sparse_.reserve(n);
    height_ = height;
    for (size_t i = 0; i < n; ++i) {
      const uint64_t key = cell(rows[i], columns[i]);
      if (dense_) cells_[key] = static_cast<uint32_t>(i);
      else sparse_[key] = static_cast<uint32_t>(i);
    }
  }
  uint32_t at(int64_t row, int64_t column) const {
    if (row < row0_ || column < col0_) return kEmpty;
    if (static_cast<uint64_t>(row - row0_) >= height_ || static_cast<uint64_t>(column - col0_) >= width_) return kEmpty;
    const uint64_t key = cell(row, column);
    if (dense_) return cells_[key];
    auto it = sparse_.find(key);
    return it == sparse_.end() ? kEmpty : it->second;
  }

 private:
  uint64_t cell(int64_t row, int64_t column) const {
    return static_cast<uint64_t>(row - row0_) * width_ + static_cast<uint64_t>(column - col0_);
  }
  int64_t row0_ = 0, col0_ = 0;
  uint64_t width_ = 1, height_ = 1;
  bool dense_ = true;
  std::vector<uint32_t> cells_;
  std::unordered_map<uint64_t, uint32_t> sparse_;
};

}  // namespace

std::vector<float> grid_normals(const double* p, size_t n, const int64_t* rows, const int64_t* columns,
                                const double scanner[3]) {
  std::vector<float> out(3 * n);
  if (n == 0) return out;
  if (n >= kEmpty) throw Error("grid_normals: more than 2^32 - 1 points");
  for (size_t i = 0; i < n; ++i)
    if (std::llabs(rows[i]) > (int64_t{1} << 40) || std::llabs(columns[i]) > (int64_t{1} << 40))
      throw Error("grid_normals: row or column index beyond 2^40");
  const GridIndex grid(rows, columns, n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const double* pi = p + 3 * i;
      // The difference to the nearer of the two neighbours along one grid direction.
      auto tangent = [&](uint32_t before, uint32_t after, double t[3]) {
        double best = std::numeric_limits<double>::infinity();
        for (const uint32_t j : {before, after}) {
          if (j == kEmpty || j == i) continue;
          const double sign = j == after ? 1.0 : -1.0;
          const double d[3] = {sign * (p[3 * j] - pi[0]), sign * (p[3 * j + 1] - pi[1]), sign * (p[3 * j + 2] - pi[2])};
          const double len = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
          if (len > 0 && len < best) best = len, t[0] = d[0], t[1] = d[1], t[2] = d[2];
        }
        return best < std::numeric_limits<double>::infinity();
      };
      double along_row[3] = {0, 0, 0}, along_column[3] = {0, 0, 0};
      double nrm[3] = {0, 0, 0};
      const bool ok = tangent(grid.at(rows[i], columns[i] - 1), grid.at(rows[i], columns[i] + 1), along_row) &&
                      tangent(grid.at(rows[i] - 1, columns[i]), grid.at(rows[i] + 1, columns[i]), along_column);
      if (ok) {
        nrm[0] = along_row[1] * along_column[2] - along_row[2] * along_column[1];
        nrm[1] = along_row[2] * along_column[0] - along_row[0] * along_column[2];
        nrm[2] = along_row[0] * along_column[1] - along_row[1] * along_column[0];
      }
      const double view[3] = {scanner[0] - pi[0], scanner[1] - pi[1], scanner[2] - pi[2]};
      double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      if (!(len > 0) || !std::isfinite(len)) {
        std::copy(view, view + 3, nrm);
        len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        if (!(len > 0) || !std::isfinite(len)) nrm[0] = 0, nrm[1] = 0, nrm[2] = 1, len = 1;
      }
      const double facing = nrm[0] * view[0] + nrm[1] * view[1] + nrm[2] * view[2] < 0 ? -1.0 : 1.0;
      for (int a = 0; a < 3; ++a) out[3 * i + a] = static_cast<float>(facing * nrm[a] / len);
    }
  });
  return out;
}

}  // namespace pointnpr::geometry
