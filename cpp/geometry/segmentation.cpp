#include "geometry/segmentation.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numeric>

#include "core/error.h"
#include "core/progress.h"

namespace pointnpr::geometry {

namespace {
struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent[a] = b;
  }
};
}  // namespace

int32_t relabel_by_size(std::vector<int32_t>& labels) {
  int32_t max_label = -1;
  for (int32_t l : labels) max_label = std::max(max_label, l);
  if (max_label < 0) return 0;
  std::vector<uint64_t> size(size_t(max_label) + 1, 0);
  std::vector<uint64_t> first(size_t(max_label) + 1, std::numeric_limits<uint64_t>::max());
  for (size_t i = 0; i < labels.size(); ++i)
    if (labels[i] >= 0) {
      ++size[size_t(labels[i])];
      first[size_t(labels[i])] = std::min<uint64_t>(first[size_t(labels[i])], i);
    }
  std::vector<int32_t> order;
  for (int32_t l = 0; l <= max_label; ++l)
    if (size[size_t(l)]) order.push_back(l);
  std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
    return size[size_t(a)] != size[size_t(b)] ? size[size_t(a)] > size[size_t(b)] : first[size_t(a)] < first[size_t(b)];
  });
  std::vector<int32_t> remap(size_t(max_label) + 1, -1);
  for (size_t r = 0; r < order.size(); ++r) remap[size_t(order[r])] = int32_t(r);
  for (int32_t& l : labels)
    if (l >= 0) l = remap[size_t(l)];
  return int32_t(order.size());
}

Components connected_components(std::span<const double> xyz, int level, uint32_t min_points, double cell_size,
                                bool float32) {
  if (xyz.size() % 3 != 0) throw Error("positions must be an N x 3 array");
  if (cell_size <= 0.0 && (level < 1 || level > 21)) throw Error("octree level must be in [1, 21]");
  if (!(cell_size >= 0.0) || !std::isfinite(cell_size)) throw Error("cell_size must be finite and >= 0");
  const size_t n = xyz.size() / 3;
  Components out;
  out.labels.assign(n, -1);
  if (n == 0) return out;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 q(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      throw Error("point " + std::to_string(i) + " has a non-finite coordinate");
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  // CCMiscTools::MakeMinAndMaxCubical with its default enlargement of 1%.
  const glm::dvec3 ext = hi - lo;
  const double edge = std::max({ext.x, ext.y, ext.z}) * 1.01;
  const glm::dvec3 cube_min = ((hi + lo) - glm::dvec3(edge)) * 0.5;
  const uint64_t cells_per_axis = cell_size > 0.0 ? 0 : (uint64_t(1) << level);
  double cs = cell_size > 0.0 ? cell_size : edge / double(cells_per_axis);
  if (!(cs > 0.0)) cs = 1.0;  // all points identical: a single cell
  out.cell_size = cs;
  const double max_index = cell_size > 0.0 ? double((uint64_t(1) << 21) - 1) : double(cells_per_axis - 1);
  if (cell_size > 0.0 && edge / cs > max_index) throw Error("cell_size too small: more than 2^21 cells along an axis");
  // key = x << 42 | y << 21 | z; sorted (key, point).
  std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
  if (float32 && cell_size <= 0.0) {
    // CloudCompare's DgmOctree in float (CCMiscTools::MakeMinAndMaxCubical,
    // getTheCellPosWhichIncludesThePoint at level 21, then truncation).
    float fmin[3], fmax[3];
    for (int a = 0; a < 3; ++a) {
      fmin[a] = std::numeric_limits<float>::max();
      fmax[a] = -std::numeric_limits<float>::max();
    }
    for (size_t i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) {
        const float v = float(xyz[3 * i + a]);
        fmin[a] = std::min(fmin[a], v);
        fmax[a] = std::max(fmax[a], v);
      }
    const float diag = std::max({fmax[0] - fmin[0], fmax[1] - fmin[1], fmax[2] - fmin[2]});
    const float dd = float(double(diag) * 1.01);
    float dim_min[3];
    for (int a = 0; a < 3; ++a) dim_min[a] = ((fmax[a] + fmin[a]) - dd) * 0.5f;
    const float cs0 = (dim_min[0] + dd) - dim_min[0];
    const float cs21 = cs0 / float(uint64_t(1) << 21);
    const int down = 21 - level;
    out.cell_size = double(cs0) / double(cells_per_axis);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      uint64_t c[3];
      for (int a = 0; a < 3; ++a) {
        const float q = (float(xyz[3 * i + a]) - dim_min[a]) / cs21;
        const int64_t pos = cs21 > 0.0f ? std::clamp<int64_t>(int64_t(q), 0, (int64_t(1) << 21) - 1) : 0;
        c[a] = uint64_t(pos) >> down;
      }
      keyed[i] = {c[0] << 42 | c[1] << 21 | c[2], uint32_t(i)};
    });
  } else {
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      uint64_t c[3];
      for (int a = 0; a < 3; ++a)
        c[a] = uint64_t(std::clamp(std::floor((xyz[3 * i + a] - cube_min[a]) / cs), 0.0, max_index));
      keyed[i] = {c[0] << 42 | c[1] << 21 | c[2], uint32_t(i)};
    });
  }
  Progress* progress = current_progress();
  check_cancelled(progress);
  tbb::parallel_sort(keyed.begin(), keyed.end());
  check_cancelled(progress);
  advance(progress, n);
  std::vector<uint64_t> cells;
  std::vector<uint32_t> cell_of_sorted(n);
  for (size_t s = 0; s < n; ++s) {
    if (cells.empty() || cells.back() != keyed[s].first) cells.push_back(keyed[s].first);
    cell_of_sorted[s] = uint32_t(cells.size() - 1);
  }
  const size_t m = cells.size();
  UnionFind uf(m);
  constexpr uint64_t mask = (uint64_t(1) << 21) - 1;
  // Each cell looks at its 13 "forward" neighbours (the other 13 look at
  // it): z+1 in its own row, and z-1..z+1 in the rows (x, y+1), (x+1, y-1),
  // (x+1, y), (x+1, y+1). The cells are sorted by (x, y, z), and for a fixed
  // row offset the first key to look at grows with the cell's key, so one
  // pointer per offset walks the array once: O(cells), no searches.
  const int64_t row_dx[4] = {0, 1, 1, 1}, row_dy[4] = {1, -1, 0, 1};
  size_t ptr[4] = {0, 0, 0, 0};
  const auto key_of = [](int64_t x, int64_t y, int64_t z) {
    return uint64_t(x) << 42 | uint64_t(y) << 21 | uint64_t(z);
  };
  const int64_t max_coord = int64_t(mask);
  for (size_t c = 0; c < m; ++c) {
    if (c % 65536 == 0) check_cancelled(progress);
    const int64_t x = int64_t(cells[c] >> 42), y = int64_t((cells[c] >> 21) & mask), z = int64_t(cells[c] & mask);
    if (c + 1 < m && cells[c + 1] == key_of(x, y, z + 1)) uf.unite(uint32_t(c), uint32_t(c + 1));
    for (int o = 0; o < 4; ++o) {
      const int64_t nx = x + row_dx[o], ny = y + row_dy[o];
      if (ny < 0 || ny > max_coord || nx > max_coord) continue;
      const uint64_t first_key = key_of(nx, ny, std::max<int64_t>(z - 1, 0));
      const uint64_t last_key = key_of(nx, ny, std::min<int64_t>(z + 1, max_coord));
      size_t& q = ptr[o];
      while (q < m && cells[q] < first_key) ++q;
      for (size_t j = q; j < m && cells[j] <= last_key; ++j) uf.unite(uint32_t(c), uint32_t(j));
    }
  }
  advance(progress, n);
  std::vector<uint32_t> comp_size(m, 0);
  for (size_t s = 0; s < n; ++s) ++comp_size[uf.find(cell_of_sorted[s])];
  for (size_t s = 0; s < n; ++s) {
    const uint32_t root = uf.find(cell_of_sorted[s]);
    out.labels[keyed[s].second] = comp_size[root] >= min_points ? int32_t(root) : -1;
  }
  out.count = relabel_by_size(out.labels);
  advance(progress, n);
  return out;
}

namespace {
double color_dist2(uint32_t a, uint32_t b) {
  double s = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double d = double((a >> (8 * c)) & 255) - double((b >> (8 * c)) & 255);
    s += d * d;
  }
  return s;
}
}  // namespace

Components region_growing_rgb(const LocalPoints& pts, const Neighborhoods& nb, const std::vector<uint32_t>& colors,
                              const RegionGrowingParams& prm) {
  const size_t n = pts.size();
  if (colors.size() != n) throw Error("region growing needs one colour per point");
  if (!(prm.distance_threshold >= 0.0) || !(prm.point_color_threshold >= 0.0) || !(prm.region_color_threshold >= 0.0))
    throw Error("region growing thresholds must be >= 0");
  Components out;
  out.labels.assign(n, -1);
  if (n == 0) return out;
  // PCL squares its thresholds in float (setPointColorThreshold, ...).
  const auto squared = [](double t) { return double(float(t) * float(t)); };
  const double p2p = squared(prm.point_color_threshold), r2r = squared(prm.region_color_threshold);
  const float dist2_max = float(squared(prm.distance_threshold));
  // PCL searches region_neighbours points per point, grows over the first k.
  const int region_k = std::min(prm.region_neighbours > 0 ? prm.region_neighbours : prm.k, nb.k);
  const int grow_k = std::min(prm.k, region_k);
  // (1) growth from seeds in index order.
  std::vector<int32_t> seg(n, -1);
  int32_t nseg = 0;
  std::deque<uint32_t> queue;
  std::vector<uint32_t> sorted_of(n);
  for (size_t s = 0; s < n; ++s) sorted_of[pts.original[s]] = uint32_t(s);
  Progress* progress = current_progress();
  for (size_t i = 0; i < n; ++i) {
    if (i % 16384 == 0) {
      check_cancelled(progress);
      advance(progress, std::min<size_t>(16384, n - i));
    }
    const uint32_t seed = sorted_of[i];  // seeds in the caller's index order
    if (seg[seed] >= 0) continue;
    seg[seed] = nseg;
    queue.push_back(seed);
    while (!queue.empty()) {
      const uint32_t p = queue.front();
      queue.pop_front();
      for (int j = 0; j < grow_k; ++j) {
        const uint32_t q = nb.at(p)[j];
        if (seg[q] >= 0 || color_dist2(colors[p], colors[q]) > p2p) continue;
        seg[q] = nseg;
        queue.push_back(q);
      }
    }
    ++nseg;
  }
  // Segment sizes and mean colours (PCL: float division, truncated).
  std::vector<uint64_t> seg_size(static_cast<size_t>(nseg), 0);
  std::vector<std::array<uint64_t, 3>> sum(static_cast<size_t>(nseg), {0, 0, 0});
  for (size_t i = 0; i < n; ++i) {
    ++seg_size[size_t(seg[i])];
    for (int c = 0; c < 3; ++c) sum[size_t(seg[i])][size_t(c)] += (colors[i] >> (8 * c)) & 255;
  }
  std::vector<uint32_t> mean(static_cast<size_t>(nseg));
  for (size_t s = 0; s < size_t(nseg); ++s) {
    uint32_t packed = 0;
    for (int c = 0; c < 3; ++c)
      packed |= uint32_t(float(sum[s][size_t(c)]) / float(seg_size[s])) << (8 * c);
    mean[s] = packed;
  }
  // PCL's findRegionsKNN: the nearest point distance from a segment to each
  // segment that its points' region_k nearest neighbours reach; the
  // region_k nearest of those (by distance, then segment) are its
  // neighbours. Points grouped by segment, one pass over their neighbours.
  std::vector<uint32_t> seg_start(static_cast<size_t>(nseg) + 1, 0), by_seg(n);
  for (size_t i = 0; i < n; ++i) ++seg_start[size_t(seg[i]) + 1];
  for (size_t s = 0; s < size_t(nseg); ++s) seg_start[s + 1] += seg_start[s];
  {
    std::vector<uint32_t> fill(seg_start.begin(), seg_start.end() - 1);
    for (size_t i = 0; i < n; ++i) by_seg[fill[size_t(seg[i])]++] = uint32_t(i);
  }
  std::vector<std::vector<std::pair<int32_t, float>>> seg_nb(static_cast<size_t>(nseg));
  {
    std::vector<float> nearest(static_cast<size_t>(nseg), std::numeric_limits<float>::infinity());
    std::vector<int32_t> touched;
    for (int32_t s = 0; s < nseg; ++s) {
      for (uint32_t at = seg_start[size_t(s)]; at < seg_start[size_t(s) + 1]; ++at) {
        const uint32_t i = by_seg[at];
        for (int j = 0; j < region_k; ++j) {
          const int32_t o = seg[nb.at(i)[j]];
          if (o == s) continue;
          const float d2 = nb.d2_at(i)[j];
          if (nearest[size_t(o)] == std::numeric_limits<float>::infinity()) touched.push_back(o);
          nearest[size_t(o)] = std::min(nearest[size_t(o)], d2);
        }
      }
      auto& list = seg_nb[size_t(s)];
      for (int32_t o : touched) list.emplace_back(o, nearest[size_t(o)]);
      const auto closer = [](const std::pair<int32_t, float>& a, const std::pair<int32_t, float>& b) {
        return a.second != b.second ? a.second < b.second : a.first < b.first;
      };
      if (list.size() > size_t(region_k)) {
        std::nth_element(list.begin(), list.begin() + region_k, list.end(), closer);
        list.resize(size_t(region_k));
      }
      std::sort(list.begin(), list.end(), closer);
      for (int32_t o : touched) nearest[size_t(o)] = std::numeric_limits<float>::infinity();
      touched.clear();
    }
  }
  check_cancelled(progress);
  // (2) homogeneous regions: one greedy pass as PCL does.
  std::vector<int32_t> region(static_cast<size_t>(nseg), -1);
  std::vector<uint64_t> region_size;
  int32_t nreg = 0;
  for (int32_t s = 0; s < nseg; ++s) {
    if (region[size_t(s)] < 0) {
      region[size_t(s)] = nreg++;
      region_size.push_back(seg_size[size_t(s)]);
    }
    const int32_t cur = region[size_t(s)];
    for (const auto& [o, d2] : seg_nb[size_t(s)]) {
      if (d2 > dist2_max || region[size_t(o)] >= 0) continue;
      if (color_dist2(mean[size_t(s)], mean[size_t(o)]) < r2r) {
        region[size_t(o)] = cur;
        region_size[size_t(cur)] += seg_size[size_t(o)];
      }
    }
  }
  // (3) small regions join their nearest neighbouring region.
  UnionFind merged(static_cast<size_t>(nreg));
  std::vector<uint64_t> msize(region_size);
  std::vector<std::vector<int32_t>> members(static_cast<size_t>(nreg));
  for (int32_t s = 0; s < nseg; ++s) members[size_t(region[size_t(s)])].push_back(s);
  for (int32_t r = 0; r < nreg; ++r) {
    const uint32_t root = merged.find(uint32_t(r));
    if (msize[root] >= prm.min_cluster_size) continue;
    float best = std::numeric_limits<float>::max();
    int32_t best_region = -1;
    for (int32_t s : members[root])
      for (const auto& [o, d2] : seg_nb[size_t(s)]) {
        const uint32_t other = merged.find(uint32_t(region[size_t(o)]));
        if (other != root && d2 < best) {
          best = d2;
          best_region = int32_t(other);
        }
      }
    if (best_region < 0) continue;
    const uint64_t total = msize[root] + msize[size_t(best_region)];
    merged.unite(root, uint32_t(best_region));
    const uint32_t into = merged.find(root);
    const uint32_t from = into == root ? uint32_t(best_region) : root;
    msize[into] = total;
    auto& dst = members[into];
    dst.insert(dst.end(), members[from].begin(), members[from].end());
    members[from].clear();
    members[from].shrink_to_fit();
  }
  check_cancelled(progress);
  // (4) size filter.
  std::vector<int32_t> sorted_labels(n);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t root = merged.find(uint32_t(region[size_t(seg[i])]));
    const uint64_t sz = msize[root];
    sorted_labels[i] = sz >= prm.min_cluster_size && sz <= prm.max_cluster_size ? int32_t(root) : -1;
  }
  out.labels = pts.to_original(sorted_labels);
  out.count = relabel_by_size(out.labels);
  advance(progress, n);
  return out;
}

std::vector<Group> split_by_attribute(std::span<const int64_t> values) {
  std::map<int64_t, std::vector<uint32_t>> groups;
  for (size_t i = 0; i < values.size(); ++i) groups[values[i]].push_back(uint32_t(i));
  std::vector<Group> out;
  out.reserve(groups.size());
  for (auto& [v, idx] : groups) out.push_back({v, std::move(idx)});
  return out;
}

}  // namespace pointnpr::geometry
