#include "io/scan_cache_stream.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>

#include "core/error.h"
#include "core/morton.h"
#include "core/progress.h"
#include "io/scan_cache_writer.h"
#include "render/gpu_cloud.h"  // chunk_queue_order
#include "scene/point_cloud.h"

namespace pointnpr::io {
namespace {

constexpr int kMaxBucketBits = 20;  // 2^20 buckets of the first Morton bits at most (8 MB of counts)
constexpr int kRefineBits = 16;     // a too full bucket counted again in 2^16 parts

bool finite(const glm::dvec3& q) { return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z); }

// The point as the in-memory import's PointCloud sees it: its float offset
// from the origin, read back in double.
glm::dvec3 offset_point(const glm::dvec3& p, const glm::dvec3& origin) {
  return glm::dvec3(glm::vec3(p - origin));
}
glm::dvec3 point(const double* p) { return {p[0], p[1], p[2]}; }

// One cache: a class (or all points) and what each pass learns of it.
struct Group {
  int classification = -1;
  uint64_t rows = 0, finite = 0;
  glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
  double scale = 1.0;
  int shift = 63;                   // bucket = code >> shift
  std::vector<uint64_t> buckets;    // points per bucket
  std::vector<uint64_t> heavy;      // buckets too full for a run, ascending (kept for the report)
  std::vector<std::vector<uint64_t>> refined;  // per heavy bucket: points per part
  std::vector<uint64_t> run_start;  // first Morton code of each run, ascending (run_start[0] = 0)
  std::vector<uint64_t> run_points, run_at;  // points of each run; its first record in the sort file
  std::vector<std::vector<uint8_t>> run_buffer;  // pass 4: records not yet written, per run
  std::vector<uint64_t> run_next;                // pass 4: the next record's place, per run
  std::string path;

  uint64_t code(const glm::dvec3& q) const {
    return morton_code(uint64_t((q.x - lo.x) * scale), uint64_t((q.y - lo.y) * scale),
                       uint64_t((q.z - lo.z) * scale));
  }
  size_t run_of(uint64_t code) const {
    return size_t(std::upper_bound(run_start.begin(), run_start.end(), code) - run_start.begin()) - 1;
  }
};

// The file the runs are scattered into; removed when done.
class SortFile {
 public:
  explicit SortFile(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
    if (fd_ < 0) fail("cannot create");
  }
  ~SortFile() {
    if (fd_ >= 0) ::close(fd_);
    ::unlink(path_.c_str());
  }
  void write(const uint8_t* data, size_t bytes, uint64_t at) {
    while (bytes > 0) {
      const ssize_t w = ::pwrite(fd_, data, bytes, off_t(at));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) fail("cannot write");
      data += w, bytes -= size_t(w), at += uint64_t(w);
    }
  }
  void read(uint8_t* data, size_t bytes, uint64_t at) const {
    while (bytes > 0) {
      const ssize_t r = ::pread(fd_, data, bytes, off_t(at));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) fail("cannot read");
      data += r, bytes -= size_t(r), at += uint64_t(r);
    }
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw Error(std::string(what) + " the scan cache's sort file " + path_ + ": " + std::strerror(errno));
  }
  std::string path_;
  int fd_ = -1;
};

// A point's record in the sort file: float offsets, id, then the cache's
// attributes (packed colour, intensity, class), unaligned.
struct RecordLayout {
  size_t color = 0, intensity = 0, classification = 0, bytes = 16;
  explicit RecordLayout(uint32_t flags) {
    if (flags & uint32_t(Attribute::Color)) color = bytes, bytes += 4;
    if (flags & uint32_t(Attribute::Intensity)) intensity = bytes, bytes += 4;
    if (flags & uint32_t(Attribute::Classification)) classification = bytes, bytes += 1;
  }
};

template <class T>
T load(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// Consecutive cells (code ranges with their point counts, ascending) joined
// into runs of at most `limit` points; a fuller cell is a run of its own.
void make_runs(Group& g, const std::vector<std::pair<uint64_t, uint64_t>>& cells, uint64_t limit) {
  g.run_start.assign(1, 0);
  g.run_points.assign(1, 0);
  for (const auto& [start, count] : cells) {
    if (count == 0) continue;
    if (g.run_points.back() > 0 && g.run_points.back() + count > limit) {
      g.run_start.push_back(start);
      g.run_points.push_back(0);
    }
    g.run_points.back() += count;
  }
}

}  // namespace

std::vector<StreamedCache> write_scan_caches(const ScanPass& pass,
                                             const std::function<std::string(int)>& path_for,
                                             const StreamedCacheOptions& o) {
  if (o.max_chunk_points == 0) throw Error("max_chunk_points must be positive");
  Progress* progress = current_progress();
  auto advance = [&](uint64_t n) {
    if (!progress) return;
    progress->check();
    progress->advance(n);
  };

  // Pass 1: the groups, their rows, finite points and bounds; which
  // attributes the scan has; per block, its rows in each group (a point's id
  // is its row within its group, and LAZ blocks may come in any order).
  std::array<std::unique_ptr<Group>, 256> by_class;
  Group all;
  std::map<uint64_t, std::vector<uint64_t>> block_rows;  // split: block's first point -> rows per class
  bool has_rgb = false, has_intensity = false, has_classification = false;
  uint16_t max_rgb = 0;
  uint64_t scan_points = 0;
  auto group_of = [&](const ScanBlock& b, size_t i) -> Group& {
    if (!o.split_by_classification) return all;
    std::unique_ptr<Group>& g = by_class[b.classification[i]];
    if (!g) g = std::make_unique<Group>(), g->classification = b.classification[i];
    return *g;
  };
  pass([&](const ScanBlock& b) {
    if (o.split_by_classification && !b.classification)
      throw Error("the scan has no classification to split by");
    has_rgb |= b.rgb16 != nullptr;
    has_intensity |= b.intensity != nullptr;
    has_classification |= b.classification != nullptr;
    if (b.rgb16)
      for (size_t i = 0; i < 3 * b.count; ++i) max_rgb = std::max(max_rgb, b.rgb16[i]);
    std::vector<uint64_t>* rows = nullptr;
    if (o.split_by_classification) (rows = &block_rows[b.first])->assign(256, 0);
    for (size_t i = 0; i < b.count; ++i) {
      Group& g = group_of(b, i);
      ++g.rows;
      if (rows) ++(*rows)[b.classification[i]];
      const glm::dvec3 q = point(b.positions + 3 * i);
      if (!finite(q)) continue;
      ++g.finite;
      g.lo = glm::min(g.lo, q);  // in the file's coordinates until the origin is known
      g.hi = glm::max(g.hi, q);
    }
    scan_points += b.count;
    advance(0);
  });
  // Five steps of the scan's size: the passes and the runs' sorting.
  if (progress) progress->expect(5 * scan_points);
  advance(scan_points);

  std::vector<Group*> groups;
  if (o.split_by_classification) {
    for (auto& g : by_class)
      if (g) groups.push_back(g.get());
  } else if (all.rows > 0) {
    groups.push_back(&all);
  }
  // The origin, then each group's bounds as offsets from it: rounding an
  // offset to float is monotonic, so the offsets' bounds are the bounds'.
  glm::dvec3 origin = o.origin;
  if (o.recentre) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (Group* g : groups)
      if (g->finite) lo = glm::min(lo, g->lo), hi = glm::max(hi, g->hi);
    origin = lo.x <= hi.x ? glm::dvec3(std::nearbyint((lo.x + hi.x) * 0.5), std::nearbyint((lo.y + hi.y) * 0.5),
                                       std::nearbyint((lo.z + hi.z) * 0.5))
                          : glm::dvec3(0.0);
  }
  for (Group* g : groups) {
    if (g->finite == 0) continue;
    g->lo = offset_point(g->lo, origin);
    g->hi = offset_point(g->hi, origin);
  }
  for (Group* g : groups)
    if (g->rows > std::numeric_limits<uint32_t>::max() / 2)
      throw Error("point cloud too large (more than 2^31 points" +
                  std::string(o.split_by_classification ? " of one class)" : ")"));

  // The cache's attributes, as the importer hands them to a PointCloud:
  // colour only when some point has one (all zero: none, as read_las).
  uint32_t flags = 0;
  if (has_rgb && max_rgb > 0) flags |= uint32_t(Attribute::Color);
  if (has_intensity) flags |= uint32_t(Attribute::Intensity);
  if (has_classification) flags |= uint32_t(Attribute::Classification);
  const int rgb_shift = max_rgb > 255 ? 8 : 0;  // read_las's rule: any value above 255 means 16 bits
  const RecordLayout rec(flags);
  // A run's records and its sort keys in memory (both at once).
  const uint64_t run_limit =
      std::max<uint64_t>(o.max_chunk_points, o.memory_bytes / 2 / (rec.bytes + 16));

  // Every group's first ids per block (prefix sums of pass 1 in file order).
  std::map<uint64_t, std::array<uint64_t, 256>> block_base;
  if (o.split_by_classification) {
    std::array<uint64_t, 256> next{};
    for (const auto& [first, rows] : block_rows) {
      block_base[first] = next;
      for (int c = 0; c < 256; ++c) next[c] += rows[c];
    }
    block_rows.clear();
  }
  // Calls fn(group, point, id, offset point) for every finite point of a block.
  auto for_points = [&](const ScanBlock& b, const auto& fn) {
    std::array<uint64_t, 256> next{};
    if (o.split_by_classification) {
      auto it = block_base.find(b.first);
      if (it == block_base.end()) throw Error("the scan changed while it was read (a block moved)");
      next = it->second;
    }
    for (size_t i = 0; i < b.count; ++i) {
      Group& g = group_of(b, i);
      const uint64_t id = o.split_by_classification ? next[b.classification[i]]++ : b.first + i;
      const glm::dvec3 q = offset_point(point(b.positions + 3 * i), origin);
      if (finite(q)) fn(g, i, uint32_t(id), q);
    }
  };

  // Pass 2: the Morton buckets (PointCloud's code: the same scale on the
  // same bounds, so the same order).
  for (Group* g : groups) {
    if (g->finite == 0) continue;
    const glm::dvec3 extent = glm::max(g->hi - g->lo, glm::dvec3(1e-12));
    g->scale = double((1u << 21) - 1) / std::max({extent.x, extent.y, extent.z});
    int bits = 0;
    while (bits < kMaxBucketBits && (uint64_t(64) << (bits + 1)) <= g->finite) ++bits;
    g->shift = 63 - bits;
    g->buckets.assign(size_t(1) << bits, 0);
  }
  pass([&](const ScanBlock& b) {
    for_points(b, [&](Group& g, size_t, uint32_t, const glm::dvec3& q) { ++g.buckets[g.code(q) >> g.shift]; });
    advance(b.count);
  });

  // Pass 3 (only when some bucket alone exceeds a run): those buckets
  // counted again in finer parts.
  bool refine = false;
  for (Group* g : groups) {
    for (size_t k = 0; k < g->buckets.size(); ++k)
      if (g->buckets[k] > run_limit) g->heavy.push_back(k);
    g->refined.assign(g->heavy.size(), std::vector<uint64_t>(size_t(1) << kRefineBits, 0));
    refine |= !g->heavy.empty();
  }
  if (refine) {
    pass([&](const ScanBlock& b) {
      for_points(b, [&](Group& g, size_t, uint32_t, const glm::dvec3& q) {
        const uint64_t c = g.code(q);
        auto it = std::lower_bound(g.heavy.begin(), g.heavy.end(), c >> g.shift);
        if (it != g.heavy.end() && *it == c >> g.shift)
          ++g.refined[size_t(it - g.heavy.begin())][(c >> (g.shift - kRefineBits)) & ((1u << kRefineBits) - 1)];
      });
      advance(b.count);
    });
  } else {
    advance(scan_points);
  }

  // The runs, and where each starts in the sort file.
  uint64_t records = 0;
  size_t runs = 0;
  for (Group* g : groups) {
    std::vector<std::pair<uint64_t, uint64_t>> cells;
    size_t h = 0;
    for (size_t k = 0; k < g->buckets.size(); ++k) {
      if (h < g->heavy.size() && g->heavy[h] == k) {
        for (size_t s = 0; s < g->refined[h].size(); ++s)
          cells.push_back({uint64_t(k) << g->shift | uint64_t(s) << (g->shift - kRefineBits), g->refined[h][s]});
        ++h;
      } else {
        cells.push_back({uint64_t(k) << g->shift, g->buckets[k]});
      }
    }
    g->buckets = {};
    g->refined = {};
    make_runs(*g, cells, run_limit);
    g->run_at.resize(g->run_points.size());
    for (size_t r = 0; r < g->run_points.size(); ++r) g->run_at[r] = records, records += g->run_points[r];
    runs += g->run_points.size();
  }
  if (groups.empty()) throw Error("the scan has no points; no cache was written");
  for (Group* g : groups) g->path = path_for(g->classification);

  // Pass 4: every point's record into its run's part of the sort file,
  // through a buffer per run.
  SortFile sort_file(groups.front()->path + ".sorting");
  {
    const size_t buffer_records =
        std::clamp<size_t>(o.memory_bytes / 4 / std::max<size_t>(runs, 1) / rec.bytes, 256, size_t(1) << 16);
    const size_t buffer_bytes = buffer_records * rec.bytes;
    for (Group* g : groups) {
      g->run_next = g->run_at;
      g->run_buffer.assign(g->run_points.size(), {});
      for (auto& b : g->run_buffer) b.reserve(buffer_bytes);
    }
    auto flush = [&](Group& g, size_t r) {
      std::vector<uint8_t>& bytes = g.run_buffer[r];
      sort_file.write(bytes.data(), bytes.size(), g.run_next[r] * rec.bytes);
      g.run_next[r] += bytes.size() / rec.bytes;
      bytes.clear();
    };
    pass([&](const ScanBlock& b) {
      for_points(b, [&](Group& g, size_t i, uint32_t id, const glm::dvec3& q) {
        const size_t r = g.run_of(g.code(q));
        std::vector<uint8_t>& bytes = g.run_buffer[r];
        const size_t at = bytes.size();
        bytes.resize(at + rec.bytes);
        uint8_t* w = bytes.data() + at;
        const glm::vec3 f(q);
        std::memcpy(w, &f, 12);
        std::memcpy(w + 12, &id, 4);
        if (rec.color) {
          const uint16_t* c = b.rgb16 + 3 * i;
          const uint32_t packed = uint32_t(uint8_t(c[0] >> rgb_shift)) | uint32_t(uint8_t(c[1] >> rgb_shift)) << 8 |
                                  uint32_t(uint8_t(c[2] >> rgb_shift)) << 16 | 255u << 24;
          std::memcpy(w + rec.color, &packed, 4);
        }
        if (rec.intensity) std::memcpy(w + rec.intensity, b.intensity + i, 4);
        if (rec.classification) w[rec.classification] = b.classification[i];
        if (bytes.size() >= buffer_bytes) flush(g, r);
      });
      advance(b.count);
    });
    for (Group* g : groups) {
      for (size_t r = 0; r < g->run_buffer.size(); ++r) flush(*g, r);
      g->run_buffer = {};
      for (size_t r = 0; r < g->run_points.size(); ++r)
        if (g->run_next[r] != g->run_at[r] + g->run_points[r])
          throw Error("the scan changed while it was read (a run's count differs)");
    }
  }

  // Each group's runs in order, sorted by (code, id) as PointCloud sorts its
  // points, cut into chunks of max_chunk_points.
  std::vector<StreamedCache> written;
  try {
    for (Group* g : groups) {
      const uint32_t cap = o.max_chunk_points;
      const size_t chunk_count = size_t((g->finite + cap - 1) / cap);
      ScanCacheFileWriter out(g->path, flags, chunk_count);
      std::vector<glm::dvec3> q(cap);
      std::vector<glm::vec3> local(cap);
      std::vector<uint32_t> ids(cap), colors(rec.color ? cap : 0), classes(rec.classification ? cap : 0),
          queue(cap);
      std::vector<float> intensity(rec.intensity ? cap : 0);
      uint32_t filled = 0;
      auto emit = [&] {
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (uint32_t k = 0; k < filled; ++k) lo = glm::min(lo, q[k]), hi = glm::max(hi, q[k]);
        const PointChunk box = chunk_around(lo, hi);
        for (uint32_t k = 0; k < filled; ++k) local[k] = glm::vec3(q[k] - box.origin);
        chunk_queue_order(ids.data(), filled, queue.data());
        ScanCacheChunkIn in;
        in.origin = box.origin;
        in.local_min = box.local_min;
        in.local_max = box.local_max;
        in.count = filled;
        in.positions = local.data();
        in.point_index = ids.data();
        in.colors = rec.color ? colors.data() : nullptr;
        in.intensity = rec.intensity ? intensity.data() : nullptr;
        in.classification = rec.classification ? classes.data() : nullptr;
        in.queue = queue.data();
        out.add(in);
        filled = 0;
      };
      std::vector<uint8_t> run;
      struct Key {
        uint64_t code;
        uint32_t id, record;
        bool operator<(const Key& k) const { return code != k.code ? code < k.code : id < k.id; }
      };
      std::vector<Key> keys;
      for (size_t r = 0; r < g->run_points.size(); ++r) {
        const uint64_t n = g->run_points[r];
        run.resize(n * rec.bytes);
        sort_file.read(run.data(), run.size(), g->run_at[r] * rec.bytes);
        keys.resize(n);
        for (uint64_t k = 0; k < n; ++k) {
          const uint8_t* p = run.data() + k * rec.bytes;
          keys[k] = {g->code(glm::dvec3(load<glm::vec3>(p))), load<uint32_t>(p + 12), uint32_t(k)};
        }
        std::sort(keys.begin(), keys.end());
        for (const Key& key : keys) {
          const uint8_t* p = run.data() + uint64_t(key.record) * rec.bytes;
          q[filled] = glm::dvec3(load<glm::vec3>(p));
          ids[filled] = key.id;
          if (rec.color) colors[filled] = load<uint32_t>(p + rec.color);
          if (rec.intensity) intensity[filled] = load<float>(p + rec.intensity);
          if (rec.classification) classes[filled] = p[rec.classification];
          if (++filled == cap) emit();
        }
        advance(n);
      }
      if (filled > 0) emit();
      out.finish(g->finite, g->finite ? g->lo : glm::dvec3(0.0), g->finite ? g->hi : glm::dvec3(0.0));
      written.push_back({g->classification, g->path, g->finite, g->rows, g->run_points.size(), g->heavy.size(), origin});
    }
  } catch (...) {
    for (const StreamedCache& c : written) std::remove(c.path.c_str());
    throw;
  }
  return written;
}

}  // namespace pointnpr::io
