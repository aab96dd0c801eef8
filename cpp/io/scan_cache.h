#pragma once
// The out-of-core scan cache (docs/io.md#scan-cache): a scan in the
// renderer's own layout, on disk, memory-mapped on demand. A version
// header, a chunk table (double origin, float bounds, count, checksum, byte
// offset per chunk), then per chunk its points in resolution-queue order
// (render/gpu_cloud.h), attribute after attribute: the first n points of a
// chunk are its level-of-detail prefix and lie at the start of every array,
// so a frame reads (and faults in) only the prefixes it draws.
#include <atomic>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "io/mapped_file.h"
#include "scene/point_cloud.h"

namespace pointnpr::io {

constexpr char kScanCacheMagic[8] = {'P', 'N', 'P', 'R', 'S', 'C', 'A', 'N'};
constexpr uint32_t kScanCacheVersion = 1;
constexpr size_t kScanCacheHeaderBytes = 128;
constexpr size_t kScanCacheTableEntryBytes = 64;
// Chunks larger than this are refused (the writer's chunks hold 16,384).
constexpr uint32_t kScanCacheMaxChunkPoints = 1u << 24;

// CRC-32 (IEEE 802.3, reflected 0xEDB88320), slicing by 8: `crc` continues
// an earlier call's result (0 to start).
uint32_t crc32(const uint8_t* data, size_t size, uint32_t crc = 0);

// Bytes of one chunk's data with `count` points and attribute `flags`
// (bits of Attribute): every array padded to 4 bytes.
uint64_t scan_cache_chunk_bytes(uint32_t count, uint32_t flags);

// Writes `cloud` (its chunks, origins and attributes as they are; each
// chunk's points put in resolution-queue order) to `path`. Written to a
// temporary file beside it and renamed, so a failure leaves no partial
// cache; throws Error when the file cannot be written.
void write_scan_cache(const std::string& path, const PointCloud& cloud);

struct ScanCacheChunk {
  glm::dvec3 origin{0.0};
  glm::vec3 local_min{0.0f}, local_max{0.0f};
  uint32_t count = 0;
  uint32_t checksum = 0;  // crc32 of the chunk's data
  uint64_t offset = 0;    // of its data in the file
};

// One chunk's arrays in the mapped file, queue order (point i of each).
// Arrays the cache lacks are null. Not aligned for direct loads: copy.
struct ScanCacheChunkData {
  uint32_t count = 0;
  const uint8_t* positions = nullptr;       // float x, y, z offsets from the chunk's origin
  const uint8_t* point_index = nullptr;     // uint32 stable ids
  // uint32: the point's place in the chunk's spatial (Morton) order, the
  // cloud's own: a frame's points are drawn in that order, so depth ties
  // go to the same point as in the cloud the cache was written from.
  const uint8_t* layout_rank = nullptr;
  const uint8_t* colors = nullptr;          // uint32 packed RGBA8, sRGB
  const uint8_t* intensity = nullptr;       // float
  const uint8_t* classification = nullptr;  // uint8
  const uint8_t* normals = nullptr;         // float x, y, z
};

class ScanCache {
 public:
  // Maps `path` and validates the header (magic, version, checksum, size)
  // and the chunk table (checksum, offsets, counts, finite bounds). Throws
  // ReadError naming the file and what is wrong (not a cache, another
  // version, truncated, damaged).
  explicit ScanCache(const std::string& path);
  // The same on bytes in memory (fuzzing), which must outlive the cache.
  ScanCache(const std::string& name, const uint8_t* data, size_t size);

  const std::string& path() const { return file_.path(); }
  uint64_t size() const { return points_; }
  uint32_t flags() const { return flags_; }
  bool has(Attribute a) const { return (flags_ & uint32_t(a)) != 0; }
  glm::dvec3 bounds_min() const { return bounds_min_; }
  glm::dvec3 bounds_max() const { return bounds_max_; }
  const std::vector<ScanCacheChunk>& chunks() const { return chunks_; }
  uint64_t file_bytes() const { return file_.size(); }

  // Chunk `i`'s arrays; its checksum and layout ranks are verified the
  // first time (ReadError if the bytes were altered), after which its pages
  // are released.
  ScanCacheChunkData chunk(size_t i) const;
  // Gives the mapped pages back to the kernel (resident memory bounded by
  // what a frame copies, not by the file).
  void release_pages() const { file_.release(0, file_.size()); }

 private:
  [[noreturn]] void fail(const std::string& reason, int64_t offset = -1) const;
  void validate();
  MappedFile file_;
  uint64_t points_ = 0;
  uint32_t flags_ = 0;
  glm::dvec3 bounds_min_{0.0}, bounds_max_{0.0};
  std::vector<ScanCacheChunk> chunks_;
  std::unique_ptr<std::atomic<uint8_t>[]> verified_;  // per chunk: its checksum matched
};

}  // namespace pointnpr::io
