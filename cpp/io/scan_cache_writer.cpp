// The writer of the scan cache (its reader, io/scan_cache.cpp, needs
// nothing of the renderer: the fuzz target builds it alone).
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/error.h"
#include "io/scan_cache.h"
#include "io/scan_cache_layout.h"
#include "render/gpu_cloud.h"  // queue_order: the resolution queue's definition

namespace pointnpr::io {

using namespace scan_cache_layout;

namespace {

// A FILE* that is closed (and its file removed) unless commit() renamed it.
class PartialFile {
 public:
  PartialFile(const std::string& path) : path_(path), temp_(path + ".partial") {
    f_ = std::fopen(temp_.c_str(), "wb");
    if (!f_) fail(std::strerror(errno));
  }
  ~PartialFile() {
    if (f_) std::fclose(f_);
    if (!committed_) std::remove(temp_.c_str());
  }
  void write(const void* data, size_t bytes) {
    if (bytes && std::fwrite(data, 1, bytes, f_) != bytes) fail(std::strerror(errno));
  }
  void seek(long offset) {
    if (std::fseek(f_, offset, SEEK_SET) != 0) fail(std::strerror(errno));
  }
  void commit() {
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (rc != 0) fail(std::strerror(errno));
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail(std::strerror(errno));
    committed_ = true;
  }

 private:
  [[noreturn]] void fail(const char* why) const {
    throw Error("cannot write the scan cache " + path_ + ": " + why);
  }
  std::string path_, temp_;
  std::FILE* f_ = nullptr;
  bool committed_ = false;
};


}  // namespace

void write_scan_cache(const std::string& path, const PointCloud& cloud) {
  uint32_t flags = 0;
  for (Attribute a : {Attribute::Color, Attribute::Intensity, Attribute::Classification, Attribute::Normal})
    if (cloud.has(a)) flags |= uint32_t(a);
  for (uint32_t c : cloud.classification())
    if (c > 255) throw Error("cannot write the scan cache " + path + ": classification " + std::to_string(c) +
                             " does not fit the cache's 8 bits");
  const std::vector<PointChunk>& chunks = cloud.chunks();
  const std::vector<uint32_t> order = queue_order(cloud);
  const uint64_t table_bytes = kScanCacheTableEntryBytes * chunks.size();
  const uint64_t data_offset = kScanCacheHeaderBytes + table_bytes;

  PartialFile out(path);
  std::vector<uint8_t> table(table_bytes, 0);
  out.write(std::vector<uint8_t>(data_offset, 0).data(), data_offset);  // header and table, filled in at the end
  std::vector<uint8_t> data;
  uint64_t offset = data_offset;
  for (size_t ci = 0; ci < chunks.size(); ++ci) {
    const PointChunk& ch = chunks[ci];
    const uint32_t n = ch.count;
    data.assign(scan_cache_chunk_bytes(n, flags), 0);
    uint8_t* w = data.data();
    const uint32_t* q = order.data() + ch.first;  // chunk-local indices in queue order
    for (uint32_t i = 0; i < n; ++i) store_vec3(w + 12 * i, cloud.local_positions()[ch.first + q[i]]);
    w += 12 * uint64_t(n);
    for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, cloud.point_index()[ch.first + q[i]]);
    w += 4 * uint64_t(n);
    for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, q[i]);
    w += 4 * uint64_t(n);
    if (flags & uint32_t(Attribute::Color)) {
      for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, cloud.colors()[ch.first + q[i]]);
      w += 4 * uint64_t(n);
    }
    if (flags & uint32_t(Attribute::Intensity)) {
      for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, cloud.intensity()[ch.first + q[i]]);
      w += 4 * uint64_t(n);
    }
    if (flags & uint32_t(Attribute::Classification)) {
      for (uint32_t i = 0; i < n; ++i) w[i] = uint8_t(cloud.classification()[ch.first + q[i]]);
      w += pad4(n);
    }
    if (flags & uint32_t(Attribute::Normal))
      for (uint32_t i = 0; i < n; ++i) store_vec3(w + 12 * i, cloud.normals()[ch.first + q[i]]);
    uint8_t* e = table.data() + kScanCacheTableEntryBytes * ci;
    store_dvec3(e, ch.origin);
    store_vec3(e + 24, ch.local_min);
    store_vec3(e + 36, ch.local_max);
    store(e + 48, n);
    store(e + 52, crc32(data.data(), data.size()));
    store(e + 56, offset);
    out.write(data.data(), data.size());
    offset += data.size();
  }

  std::array<uint8_t, kScanCacheHeaderBytes> h{};
  std::memcpy(h.data(), kScanCacheMagic, 8);
  store(h.data() + kVersionAt, kScanCacheVersion);
  store(h.data() + kHeaderBytesAt, uint32_t(kScanCacheHeaderBytes));
  store(h.data() + kFlagsAt, flags);
  store(h.data() + kChunkCountAt, uint32_t(chunks.size()));
  store(h.data() + kPointCountAt, uint64_t(cloud.size()));
  store_dvec3(h.data() + kBoundsMinAt, cloud.bounds_min());
  store_dvec3(h.data() + kBoundsMaxAt, cloud.bounds_max());
  store(h.data() + kTableOffsetAt, uint64_t(kScanCacheHeaderBytes));
  store(h.data() + kDataOffsetAt, data_offset);
  store(h.data() + kFileBytesAt, offset);
  store(h.data() + kTableChecksumAt, crc32(table.data(), table.size()));
  store(h.data() + kHeaderChecksumAt, crc32(h.data(), kHeaderChecksumAt));
  out.seek(0);
  out.write(h.data(), h.size());
  out.write(table.data(), table.size());
  out.commit();
}

}  // namespace pointnpr::io
