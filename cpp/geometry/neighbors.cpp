#include "geometry/neighbors.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <nanoflann.hpp>

#include "core/error.h"
#include "core/morton.h"
#include "core/progress.h"
#include "geometry/neighbor_distances.h"

namespace pointnpr::geometry {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Adaptor {
  const std::vector<glm::vec3>* pts;
  size_t kdtree_get_point_count() const { return pts->size(); }
  float kdtree_get_pt(size_t i, size_t d) const { return (*pts)[i][int(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor, float, uint32_t>,
                                                 Adaptor, 3, uint32_t>;

// (squared distance, index) as one integer, so that one comparison orders
// by distance, then index: non-negative floats order as their bits.
inline uint64_t rank_key(float d2, uint32_t index) {
  return uint64_t(std::bit_cast<uint32_t>(d2)) << 32 | index;
}
inline float key_d2(uint64_t key) { return std::bit_cast<float>(uint32_t(key >> 32)); }

// The k smallest by (squared distance, index), kept sorted. As a nanoflann
// result set it asks for ties of the current k-th distance as well (and a
// few ulps more, as the tree's lower bounds round), so that the lower index
// wins a tie whichever order the tree visits its leaves in.
class OrderedKnn {
 public:
  using DistanceType = float;
  using IndexType = uint32_t;
  OrderedKnn(size_t k, uint64_t* keys) : k_(k), keys_(keys) {}
  size_t size() const { return count_; }
  bool full() const { return count_ == k_; }
  float worstDist() const { return count_ < k_ ? kInf : key_d2(keys_[k_ - 1]) * (1.0f + 1e-6f) + 1e-37f; }
  bool addPoint(float d2, uint32_t i) {
    const uint64_t key = rank_key(d2, i);
    if (count_ == k_ && key >= keys_[k_ - 1]) return true;
    size_t j = count_ < k_ ? count_++ : k_ - 1;
    for (; j > 0 && key < keys_[j - 1]; --j) keys_[j] = keys_[j - 1];
    keys_[j] = key;
    return true;
  }

 private:
  size_t k_, count_ = 0;
  uint64_t* keys_;
};

void write_row(const uint64_t* keys, size_t k, uint32_t* index, float* dist2) {
  for (size_t j = 0; j < k; ++j) {
    index[j] = uint32_t(keys[j]);
    dist2[j] = key_d2(keys[j]);
  }
}

// A nanoflann index on a point array (leaf size 20).
struct TreeIndex {
  Adaptor adaptor;
  Tree tree;
  explicit TreeIndex(const std::vector<glm::vec3>& p)
      : adaptor{&p}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(20)) {}
  // The k (<= size) nearest of q as sorted (d2, index) keys.
  void knn(const glm::vec3& q, size_t k, uint64_t* keys) const {
    OrderedKnn result(k, keys);
    tree.findNeighbors(result, &q.x, nanoflann::SearchParams());
  }
};
}  // namespace

struct KdTree::Impl : TreeIndex {
  using TreeIndex::TreeIndex;
};

KdTree::KdTree(const std::vector<glm::vec3>& points) : impl_(std::make_unique<Impl>(points)) {}
KdTree::~KdTree() = default;
size_t KdTree::size() const { return impl_->adaptor.pts->size(); }

size_t KdTree::knn(const glm::vec3& q, size_t k, uint32_t* index, float* dist2) const {
  k = std::min(k, size());
  if (k == 0) return 0;
  thread_local std::vector<uint64_t> keys;  // no allocation per query
  keys.resize(k);
  impl_->knn(q, k, keys.data());
  write_row(keys.data(), k, index, dist2);
  return k;
}

std::vector<std::pair<uint32_t, float>> KdTree::radius(const glm::vec3& q, float r) const {
  std::vector<std::pair<uint32_t, float>> out;
  if (size() == 0 || !(r >= 0.0f)) return out;
  // nanoflann compares squared distances strictly: nudge to include r itself.
  impl_->tree.radiusSearch(&q.x, std::nextafter(r * r, std::numeric_limits<float>::max()), out,
                           nanoflann::SearchParams(32, 0.0f, true));
  return out;
}

namespace {

// The cells of one level of the Morton grid that hold points: each is the
// run of sorted points sharing a code prefix. An open-addressing hash from
// cell code to run, so that a point's 26 neighbour cells cost a probe each.
class CellLevel {
 public:
  CellLevel(const std::vector<uint64_t>& codes, int level) : shift_(3 * (21 - level)) {
    size_t cells = 0;
    for (size_t s = 0; s < codes.size(); ++s)
      if (s == 0 || (codes[s] >> shift_) != (codes[s - 1] >> shift_)) ++cells;
    size_t slots = 16;
    while (slots < 2 * cells) slots *= 2;
    mask_ = slots - 1;
    slots_.assign(slots, Slot{kEmpty, 0, 0});
    for (size_t s = 0; s < codes.size();) {
      const uint64_t cell = codes[s] >> shift_;
      size_t e = s + 1;
      while (e < codes.size() && (codes[e] >> shift_) == cell) ++e;
      size_t h = hash(cell);
      while (slots_[h].cell != kEmpty) h = (h + 1) & mask_;
      slots_[h] = Slot{cell, uint32_t(s), uint32_t(e)};
      s = e;
    }
  }
  // [begin, end) of the cell's points; empty when the cell holds none.
  std::pair<uint32_t, uint32_t> find(uint64_t cell) const {
    for (size_t h = hash(cell);; h = (h + 1) & mask_) {
      if (slots_[h].cell == cell) return {slots_[h].begin, slots_[h].end};
      if (slots_[h].cell == kEmpty) return {0, 0};
    }
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  struct Slot {
    uint64_t cell;
    uint32_t begin, end;
  };
  size_t hash(uint64_t cell) const { return size_t((cell * 0x9E3779B97F4A7C15ULL) >> 20) & mask_; }
  int shift_;
  size_t mask_ = 0;
  std::vector<Slot> slots_;
};

// All-points kNN on the Morton grid of LocalPoints, the step that dominates
// normal estimation. Cells of one level are runs of the sorted points, so a
// block of cells is a few contiguous runs: its candidates are copied once
// (x, y, z apart) and reused by the next points, which in Morton order
// mostly share the block; distances are computed four at a time, and the
// selection is branch-free, as mispredicted branches, not arithmetic, bound
// a search over a few dozen candidates.
//
// A point looks in the 3x3x3 block of cells around its own, at the finest
// level whose cells are wider than the k-th distance of the point before it
// (usually a close neighbour) grown by 20 %. If k candidates lie within
// that grown distance (or within 1.0x or 1.1x of it: the tightest that
// holds k), no point outside the block can be nearer and they are the
// answer. Otherwise the k nearest candidates stand when the k-th distance
// is below the distance to the block's outer wall; if not, the search
// repeats at the level whose cells are wider than that k-th distance,
// which then succeeds. Exact, never approximate: float rounding of the
// offsets is covered by a margin. Blocks of very many points (a lone point
// far from dense ones, a pile of distinct points finer than the finest
// cell) are brute-forced while their total stays within a budget, then
// searched in a k-d tree built on first need.
class GridKnn {
 public:
  GridKnn(const LocalPoints& pts, size_t k) : pts_(pts), k_(k) {
    const size_t n = pts.size();
    float reach = 1e-30f;
    for (int a = 0; a < 3; ++a) axis_[a].resize(n);
    for (size_t s = 0; s < n; ++s)
      for (int a = 0; a < 3; ++a) {
        axis_[a][s] = pts.points[s][a];
        reach = std::max(reach, std::abs(pts.points[s][a]));
      }
    // The float offsets and the double grid disagree by the offsets' rounding.
    slack_ = 4.0 * double(std::numeric_limits<float>::epsilon()) * double(reach);
  }

  // Per thread: the candidates of the last block, padded to a multiple of
  // four with infinitely far points.
  struct Scratch {
    int level = -1;
    uint64_t cell = ~uint64_t(0);
    std::vector<float> x, y, z;
    std::vector<uint32_t> index;
    std::vector<float> d2;
    std::vector<uint64_t> keys;
    size_t candidates = 0, padded = 0;
  };

  // The k nearest of point s as sorted (d2, index) keys; hint: a guess of
  // its k-th distance (0: none).
  void search(size_t s, float hint, Scratch& scratch, uint64_t* out) {
    const glm::vec3 p = pts_.points[s];
    const uint64_t code = pts_.code[s];
    const glm::dvec3 grid = (pts_.origin + glm::dvec3(p) - pts_.grid_min) * pts_.grid_scale;  // finest cells
    const double ball = double(hint) * 1.2;  // the largest of the three radii below
    int level = hint > 0.0f ? level_wider_than(ball) : finest_with_k(s);
    for (;;) {
      const int shift = 21 - level;
      const uint64_t c[3] = {morton_compact_bits(code) >> shift, morton_compact_bits(code >> 1) >> shift,
                             morton_compact_bits(code >> 2) >> shift};
      if (scratch.level != level || scratch.cell != code >> (3 * shift)) gather(level, c, scratch);
      if (scratch.candidates > kLargeBlock && !spend(scratch.candidates)) {
        tree_search(p, out);
        return;
      }
      const double width = double(uint64_t(1) << shift) / pts_.grid_scale;
      std::array<size_t, 3> within;
      if (hint > 0.0f && ball + slack_ < width) {
        // A ball within 1.2x the hint reaches at most the neighbouring
        // cells: if k candidates lie in it, they are the answer. The
        // tightest of three radii that holds k keeps the selection small.
        std::array<float, 3> limit2;
        for (size_t t = 0; t < 3; ++t) {
          const float r = float(double(hint) * (1.0 + 0.1 * double(t)) * (1.0 - 1e-5));
          limit2[t] = r * r;
        }
        distances(p, limit2, within, scratch);
        for (size_t t = 0; t < 3; ++t)
          if (within[t] >= k_) {
            finish(scratch, compress(limit2[t], scratch), out);
            return;
          }
      } else {
        distances(p, {kInf, kInf, kInf}, within, scratch);
      }
      const size_t found = compress(kInf, scratch);
      if (found < k_) {
        // Only when squared distances overflow float (offsets beyond 1e19).
        if (level == 0) throw Error("the points are too far apart for float distances");
        --level;
        continue;
      }
      const double kth = std::sqrt(double(finish(scratch, found, out)));
      // The block's outer wall, one cell beyond p's own (none beyond the grid).
      const uint64_t last = (uint64_t(1) << level) - 1;
      double wall = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double below = (grid[a] - double(c[a] << shift)) / pts_.grid_scale;
        if (c[a] > 0) wall = std::min(wall, below + width);
        if (c[a] < last) wall = std::min(wall, 2.0 * width - below);
      }
      if (kth * (1.0 + 1e-5) < wall - slack_ || level == 0) return;
      level = std::min(level - 1, level_wider_than(kth * 1.01 + slack_));
    }
  }

 private:
  // Blocks of more candidates than this are searched by brute force only
  // while their total stays within a budget proportional to the cloud
  // (isolated points far from dense ones are few); past it, the k-d tree.
  static constexpr size_t kLargeBlock = 4096;
  bool spend(size_t candidates) {
    if (budget_.load(std::memory_order_relaxed) < int64_t(candidates)) return false;
    return budget_.fetch_sub(int64_t(candidates), std::memory_order_relaxed) >= int64_t(candidates);
  }

  const CellLevel& cells(int level) {
    std::call_once(once_[size_t(level)], [&] { levels_[size_t(level)].emplace(pts_.code, level); });
    return *levels_[size_t(level)];
  }

  // The finest level whose cells are wider than d (in local units).
  int level_wider_than(double d) const {
    const double cells_needed = d * pts_.grid_scale;  // in finest cells
    if (!(cells_needed > 1.0)) return 21;
    if (!(cells_needed < double(uint64_t(1) << 21))) return 0;
    const int bits = int(std::bit_width(uint64_t(std::ceil(cells_needed)) - 1));  // ceil(log2)
    return 21 - bits;
  }

  // Without a hint: the finest level at which s's own cell holds k points.
  int finest_with_k(size_t s) const {
    const std::vector<uint64_t>& code = pts_.code;
    for (int level = 21; level > 0; --level) {
      const int shift = 3 * (21 - level);
      const uint64_t cell = code[s] >> shift;
      const auto lo = std::lower_bound(code.begin(), code.end(), cell << shift);
      const auto hi = std::upper_bound(lo, code.end(), ((cell + 1) << shift) - 1);
      if (size_t(hi - lo) >= k_) return level;
    }
    return 0;
  }

  void gather(int level, const uint64_t c[3], Scratch& scratch) {
    const CellLevel& table = cells(level);
    const int64_t last = (int64_t(1) << level) - 1;
    // Spread bits of the block's coordinates per axis: 3 x 3 spreads, not 27 x 3.
    uint64_t spread[3][3];
    bool inside[3][3];
    for (int a = 0; a < 3; ++a)
      for (int o = 0; o < 3; ++o) {
        const int64_t v = int64_t(c[a]) + o - 1;
        inside[a][o] = v >= 0 && v <= last;
        spread[a][o] = inside[a][o] ? morton_spread_bits(uint64_t(v)) << a : 0;
      }
    scratch.level = level;
    scratch.cell = spread[0][1] | spread[1][1] | spread[2][1];
    std::array<std::pair<uint32_t, uint32_t>, 27> runs;
    size_t nruns = 0, total = 0;
    for (int oz = 0; oz < 3; ++oz)
      for (int oy = 0; oy < 3; ++oy)
        for (int ox = 0; ox < 3; ++ox) {
          if (!inside[0][ox] || !inside[1][oy] || !inside[2][oz]) continue;
          const auto run = table.find(spread[0][ox] | spread[1][oy] | spread[2][oz]);
          runs[nruns] = run;
          nruns += run.first != run.second;
          total += run.second - run.first;
        }
    scratch.candidates = total;
    if (total > kLargeBlock && !spend(0)) return;  // the caller goes to the tree
    const size_t padded = (total + 3) / 4 * 4;
    scratch.padded = padded;
    if (scratch.x.size() < padded) {  // grown only: resizing down and up again would clear
      scratch.x.resize(padded);
      scratch.y.resize(padded);
      scratch.z.resize(padded);
      scratch.index.resize(padded);
      scratch.d2.resize(padded);
      scratch.keys.resize(padded);
    }
    size_t at = 0;
    for (size_t r = 0; r < nruns; ++r) {
      const auto [b, e] = runs[r];
      std::copy(axis_[0].begin() + b, axis_[0].begin() + e, scratch.x.begin() + long(at));
      std::copy(axis_[1].begin() + b, axis_[1].begin() + e, scratch.y.begin() + long(at));
      std::copy(axis_[2].begin() + b, axis_[2].begin() + e, scratch.z.begin() + long(at));
      for (uint32_t i = b; i < e; ++i) scratch.index[at++] = i;
    }
    for (; at < padded; ++at) scratch.x[at] = scratch.y[at] = scratch.z[at] = kInf;
  }

  // Squared distances from p to the candidates into scratch.d2, and the
  // number below each of three squared limits (the padding never counts).
  void distances(const glm::vec3& p, const std::array<float, 3>& limit2, std::array<size_t, 3>& below,
                 Scratch& scratch) const {
    squared_distances(scratch.x.data(), scratch.y.data(), scratch.z.data(), scratch.padded, {p.x, p.y, p.z}, limit2,
                      scratch.d2.data(), below);
  }

  // Keys of the candidates with d2 below limit2 into scratch.keys; returns
  // their count. Branch-free within a block of four (every key is written,
  // the count advances past those that pass); candidates come cell by cell,
  // so passing ones cluster and skipping a block where none passes is a
  // well-predicted branch.
  size_t compress(float limit2, Scratch& scratch) const {
    const float* d2 = scratch.d2.data();
    const uint32_t* index = scratch.index.data();
    uint64_t* keys = scratch.keys.data();
    size_t found = 0;
    for (size_t j = 0; j < scratch.padded; j += 4) {
      if (!(d2[j] < limit2 || d2[j + 1] < limit2 || d2[j + 2] < limit2 || d2[j + 3] < limit2)) continue;
      for (size_t l = j; l < j + 4; ++l) {
        keys[found] = rank_key(d2[l], index[l]);
        found += d2[l] < limit2 ? 1 : 0;
      }
    }
    return found;
  }

  // The k smallest of the found keys, sorted, into out; returns the k-th
  // squared distance. Few keys (the usual case): each key's rank is the
  // number of smaller keys (keys are distinct), branch-free.
  static constexpr size_t kRankedSelection = 64;
  float finish(Scratch& scratch, size_t found, uint64_t* out) const {
    uint64_t* keys = scratch.keys.data();
    if (found <= kRankedSelection) {
      for (size_t i = 0; i < found; ++i) {
        size_t rank = 0;
        for (size_t j = 0; j < found; ++j) rank += keys[j] < keys[i] ? 1 : 0;
        if (rank < k_) out[rank] = keys[i];
      }
    } else {
      std::nth_element(keys, keys + (k_ - 1), keys + found);
      std::sort(keys, keys + k_);
      std::copy(keys, keys + k_, out);
    }
    return key_d2(out[k_ - 1]);
  }

  void tree_search(const glm::vec3& p, uint64_t* out) {
    std::call_once(tree_once_, [&] { tree_.emplace(pts_.points); });
    tree_->knn(p, k_, out);
  }

  const LocalPoints& pts_;
  size_t k_;
  std::atomic<int64_t> budget_{int64_t(16 * pts_.size()) + (int64_t(1) << 20)};
  double slack_ = 0.0;
  std::array<std::vector<float>, 3> axis_;  // x, y, z apart
  std::array<std::once_flag, 22> once_;
  std::array<std::optional<CellLevel>, 22> levels_;
  std::once_flag tree_once_;
  std::optional<TreeIndex> tree_;
};

}  // namespace

// Runs of k or more identical points (a scanner's invalid returns at one
// spot, merged duplicates) would cost their length per point in any
// search; their answer is known: the first k of the run, at distance 0.
Neighborhoods knn_all(const LocalPoints& pts, int k_requested) {
  if (k_requested < 1) throw Error("k must be at least 1");
  const std::vector<glm::vec3>& points = pts.points;
  const size_t n = points.size();
  Neighborhoods nb;
  nb.k = int(std::min<size_t>(size_t(k_requested), n));
  if (n == 0) return nb;
  const size_t k = size_t(nb.k);
  nb.index.resize(n * k);
  nb.dist2.resize(n * k);

  std::vector<uint32_t> todo;
  todo.reserve(n);
  for (size_t s = 0; s < n;) {
    size_t e = s + 1;
    while (e < n && points[e] == points[s]) ++e;
    for (size_t q = s; q < e; ++q) {
      if (e - s < k) {
        todo.push_back(uint32_t(q));
        continue;
      }
      for (size_t j = 0; j < k; ++j) {
        nb.index[q * k + j] = uint32_t(s + j);
        nb.dist2[q * k + j] = 0.0f;
      }
    }
    s = e;
  }

  Progress* progress = current_progress();
  advance(progress, n - todo.size());
  GridKnn grid(pts, k);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, todo.size(), 512), [&](const tbb::blocked_range<size_t>& range) {
    check_cancelled(progress);
    GridKnn::Scratch scratch;
    std::vector<uint64_t> row(k);
    float hint = 0.0f;
    for (size_t t = range.begin(); t < range.end(); ++t) {
      const size_t q = todo[t];
      grid.search(q, hint, scratch, row.data());
      write_row(row.data(), k, nb.index.data() + q * k, nb.dist2.data() + q * k);
      hint = std::sqrt(nb.dist2[q * k + k - 1]);
    }
    advance(progress, range.size());
  });
  return nb;
}

Neighborhoods truncate(const Neighborhoods& nb, int k) {
  if (k >= nb.k) return nb;
  Neighborhoods out;
  out.k = k;
  const size_t n = nb.k ? nb.index.size() / size_t(nb.k) : 0;
  out.index.resize(n * size_t(k));
  out.dist2.resize(n * size_t(k));
  for (size_t i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      out.index[i * k + j] = nb.index[i * nb.k + j];
      out.dist2[i * k + j] = nb.dist2[i * nb.k + j];
    }
  return out;
}

}  // namespace pointnpr::geometry
