#pragma once
// A scan rendered from its out-of-core cache (io/scan_cache.h): what a frame
// draws is a prefix of each chunk's resolution queue, copied from the
// mapping into a cloud of its own, so memory follows the point budget and
// not the scan. Thread-safe.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "io/scan_cache.h"
#include "scene/point_cloud.h"

namespace pointnpr {

// Points a cached cloud draws per frame unless told otherwise.
constexpr uint64_t kDefaultStreamBudget = 4'000'000;

class CachedCloud {
 public:
  // Opens and validates the cache (ReadError when it is missing, damaged,
  // truncated or of another version).
  explicit CachedCloud(const std::string& path, uint64_t point_budget = kDefaultStreamBudget);

  const io::ScanCache& cache() const { return cache_; }
  uint64_t point_budget() const { return budget_.load(); }
  void set_point_budget(uint64_t budget) { budget_.store(budget); }

  // Per chunk, how many of its first points to draw: in proportion to
  // `weights` (a chunk's projected area; 0: not drawn), each capped by its
  // count, the capped chunks' share handed to the others (water filling),
  // `budget` in all. Deterministic: depends on nothing but the arguments.
  std::vector<uint32_t> counts_for(const std::vector<double>& weights, uint64_t budget) const;
  // Without a view: every chunk the same fraction (the proxy, a fixed budget).
  std::vector<uint32_t> counts_for_budget(uint64_t budget) const;

  // The first counts[c] points of every chunk c as a cloud (chunks that draw
  // none left out), each chunk's in its spatial order (the cloud's). The same cloud again while the counts do not change, so
  // its GPU buffers are reused; the previous one is let go before the next
  // is built. Throws ReadError when a chunk's checksum does not match.
  std::shared_ptr<const PointCloud> stream(const std::vector<uint32_t>& counts) const;
  // Heap bytes and points of the cloud stream() holds now (the stream pool).
  uint64_t stream_bytes() const;
  uint64_t stream_points() const;

 private:
  io::ScanCache cache_;
  std::atomic<uint64_t> budget_;
  mutable std::mutex mutex_;
  mutable std::vector<uint32_t> counts_;
  mutable std::shared_ptr<const PointCloud> cloud_;
};

}  // namespace pointnpr
