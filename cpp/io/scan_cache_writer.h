#pragma once
// Writing a scan cache chunk by chunk (io/scan_cache.h for the format):
// shared by write_scan_cache, which writes a PointCloud, and the streamed
// writer (io/scan_cache_stream.h), which never holds the whole scan.
#include <cstdint>
#include <cstdio>
#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace pointnpr::io {

// One chunk as the cloud lays it out (its origin, bounds and points in the
// cloud's spatial order); `queue` lists the chunk-local indices in
// resolution-queue order, the order the cache stores them in. Arrays the
// cache's flags leave out may be null.
struct ScanCacheChunkIn {
  glm::dvec3 origin{0.0};
  glm::vec3 local_min{0.0f}, local_max{0.0f};
  uint32_t count = 0;
  const glm::vec3* positions = nullptr;
  const uint32_t* point_index = nullptr;
  const uint32_t* colors = nullptr;
  const float* intensity = nullptr;
  const uint32_t* classification = nullptr;  // each below 256
  const glm::vec3* normals = nullptr;
  const uint32_t* queue = nullptr;
};

// Writes to a temporary file beside `path`, renamed by finish(): a failure
// (an Error thrown, or the writer destroyed before finish) leaves no
// partial cache.
class ScanCacheFileWriter {
 public:
  ScanCacheFileWriter(const std::string& path, uint32_t flags, size_t chunk_count);
  ~ScanCacheFileWriter();
  ScanCacheFileWriter(const ScanCacheFileWriter&) = delete;
  ScanCacheFileWriter& operator=(const ScanCacheFileWriter&) = delete;

  // The chunks in order, exactly `chunk_count` of them.
  void add(const ScanCacheChunkIn& chunk);
  void finish(uint64_t points, const glm::dvec3& bounds_min, const glm::dvec3& bounds_max);

 private:
  [[noreturn]] void fail(const char* why) const;
  void write(const void* data, size_t bytes);
  std::string path_, temp_;
  std::FILE* f_ = nullptr;
  bool committed_ = false;
  uint32_t flags_ = 0;
  size_t chunk_count_ = 0, chunks_added_ = 0;
  uint64_t offset_ = 0;
  std::vector<uint8_t> table_, data_;
};

}  // namespace pointnpr::io
