#include "scene/cached_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"

namespace pointnpr {

namespace {

// Appends element slot[k] of `src` (T values, unaligned) for every k.
template <class T>
void append_picked(std::vector<T>& out, const uint8_t* src, const std::vector<uint32_t>& slots) {
  const size_t at = out.size();
  out.resize(at + slots.size());
  for (size_t k = 0; k < slots.size(); ++k)
    std::memcpy(static_cast<void*>(&out[at + k]), src + sizeof(T) * slots[k], sizeof(T));
}

template <class T>
uint64_t heap_bytes(const std::vector<T>& v) {
  return uint64_t(v.capacity()) * sizeof(T);
}

}  // namespace

CachedCloud::CachedCloud(const std::string& path, uint64_t point_budget) : cache_(path), budget_(point_budget) {
  if (cache_.size() > std::numeric_limits<uint32_t>::max() / 2)
    throw ReadError(path, "scan caches of more than 2^31 points are not supported");
}

std::vector<uint32_t> CachedCloud::counts_for(const std::vector<double>& weights, uint64_t budget) const {
  const auto& chunks = cache_.chunks();
  if (weights.size() != chunks.size()) throw Error("one weight per chunk of the scan cache expected");
  std::vector<uint32_t> counts(chunks.size(), 0);
  // Chunks in order of count / weight: those that fill up first take all
  // their points, the rest share what is left by weight.
  std::vector<uint32_t> live;
  double weight = 0.0;
  for (uint32_t c = 0; c < chunks.size(); ++c)
    if (weights[c] > 0.0 && std::isfinite(weights[c]) && chunks[c].count > 0) {
      live.push_back(c);
      weight += weights[c];
    }
  std::sort(live.begin(), live.end(), [&](uint32_t a, uint32_t b) {
    const double ra = chunks[a].count / weights[a], rb = chunks[b].count / weights[b];
    return ra != rb ? ra < rb : a < b;
  });
  double left = double(budget);
  size_t k = 0;
  for (; k < live.size(); ++k) {
    const uint32_t c = live[k];
    if (double(chunks[c].count) > left / weight * weights[c]) break;
    counts[c] = chunks[c].count;
    left -= chunks[c].count;
    weight -= weights[c];
  }
  const double per_weight = weight > 0.0 ? left / weight : 0.0;
  for (; k < live.size(); ++k) {
    const uint32_t c = live[k];
    counts[c] = uint32_t(std::min(double(chunks[c].count), std::floor(per_weight * weights[c])));
  }
  return counts;
}

std::vector<uint32_t> CachedCloud::counts_for_budget(uint64_t budget) const {
  std::vector<double> weights;
  for (const auto& c : cache_.chunks()) weights.push_back(double(c.count));
  return counts_for(weights, budget);
}

std::shared_ptr<const PointCloud> CachedCloud::stream(const std::vector<uint32_t>& counts) const {
  const auto& chunks = cache_.chunks();
  if (counts.size() != chunks.size()) throw Error("one count per chunk of the scan cache expected");
  std::lock_guard lock(mutex_);
  if (cloud_ && counts == counts_) return cloud_;
  cloud_.reset();  // the stream pool holds one frame's points, never two
  counts_.clear();
  uint64_t total = 0;
  for (size_t c = 0; c < chunks.size(); ++c) total += std::min(counts[c], chunks[c].count);
  PointCloudChunks out;
  out.local_positions.reserve(total);
  out.point_index.reserve(total);
  if (cache_.has(Attribute::Color)) out.colors.reserve(total);
  if (cache_.has(Attribute::Intensity)) out.intensity.reserve(total);
  if (cache_.has(Attribute::Classification)) out.classification.reserve(total);
  if (cache_.has(Attribute::Normal)) out.normals.reserve(total);
  constexpr uint32_t kNoSlot = ~0u;
  std::vector<uint32_t> slot_of_rank, slots;
  for (size_t c = 0; c < chunks.size(); ++c) {
    const uint32_t n = std::min(counts[c], chunks[c].count);
    if (n == 0) continue;
    const io::ScanCacheChunkData d = cache_.chunk(c);
    PointChunk pc;
    pc.origin = chunks[c].origin;
    pc.first = uint32_t(out.local_positions.size());
    pc.count = n;
    pc.local_min = chunks[c].local_min;
    pc.local_max = chunks[c].local_max;
    out.chunks.push_back(pc);
    // The prefix in the chunk's spatial order (its layout ranks, a
    // permutation of 0..count-1: checked, the file may lie), so that a
    // point's key and the depth ties it wins are those of the cloud in memory.
    slot_of_rank.assign(chunks[c].count, kNoSlot);
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t rank;
      std::memcpy(&rank, d.layout_rank + 4 * size_t(i), 4);
      if (rank >= chunks[c].count || slot_of_rank[rank] != kNoSlot)
        throw ReadError(cache_.path(), "damaged scan cache: chunk " + std::to_string(c) +
                                           "'s layout ranks are not a permutation", int64_t(chunks[c].offset));
      slot_of_rank[rank] = i;
    }
    slots.clear();
    for (uint32_t slot : slot_of_rank)
      if (slot != kNoSlot) slots.push_back(slot);
    append_picked(out.local_positions, d.positions, slots);
    append_picked(out.point_index, d.point_index, slots);
    if (d.colors) append_picked(out.colors, d.colors, slots);
    if (d.intensity) append_picked(out.intensity, d.intensity, slots);
    if (d.classification)
      for (uint32_t slot : slots) out.classification.push_back(d.classification[slot]);
    if (d.normals) append_picked(out.normals, d.normals, slots);
  }
  out.bounds_min = cache_.bounds_min();
  out.bounds_max = cache_.bounds_max();
  cache_.release_pages();  // copied: the mapping's pages need not stay resident
  cloud_ = std::make_shared<const PointCloud>(std::move(out));
  counts_ = counts;
  return cloud_;
}

uint64_t CachedCloud::stream_bytes() const {
  std::lock_guard lock(mutex_);
  if (!cloud_) return 0;
  const PointCloud& c = *cloud_;
  return heap_bytes(c.chunks()) + heap_bytes(c.local_positions()) + heap_bytes(c.colors()) +
         heap_bytes(c.intensity()) + heap_bytes(c.classification()) + heap_bytes(c.point_index()) +
         heap_bytes(c.normals());
}

uint64_t CachedCloud::stream_points() const {
  std::lock_guard lock(mutex_);
  return cloud_ ? cloud_->size() : 0;
}

}  // namespace pointnpr
