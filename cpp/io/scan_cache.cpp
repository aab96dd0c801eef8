#include "io/scan_cache.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/error.h"
#include "render/gpu_cloud.h"  // queue_order: the resolution queue's definition

namespace pointnpr::io {

namespace {

// Byte offsets of the header's fields (docs/io.md#scan-cache).
constexpr size_t kVersionAt = 8, kHeaderBytesAt = 12, kFlagsAt = 16, kChunkCountAt = 20, kPointCountAt = 24,
                 kBoundsMinAt = 32, kBoundsMaxAt = 56, kTableOffsetAt = 80, kDataOffsetAt = 88, kFileBytesAt = 96,
                 kTableChecksumAt = 104, kHeaderChecksumAt = 124;
constexpr uint32_t kKnownFlags = uint32_t(Attribute::Color) | uint32_t(Attribute::Intensity) |
                                 uint32_t(Attribute::Classification) | uint32_t(Attribute::Normal);

std::array<std::array<uint32_t, 256>, 8> make_crc_tables() {
  std::array<std::array<uint32_t, 256>, 8> t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (uint32_t i = 0; i < 256; ++i)
    for (int s = 1; s < 8; ++s) t[s][i] = (t[s - 1][i] >> 8) ^ t[0][t[s - 1][i] & 0xFF];
  return t;
}

uint64_t pad4(uint64_t n) { return (n + 3) & ~uint64_t(3); }

template <class T>
void store(uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}

void store_dvec3(uint8_t* p, const glm::dvec3& v) {
  for (int c = 0; c < 3; ++c) store(p + 8 * c, v[c]);
}
void store_vec3(uint8_t* p, const glm::vec3& v) {
  for (int c = 0; c < 3; ++c) store(p + 4 * c, v[c]);
}
glm::dvec3 load_dvec3(const uint8_t* p) {
  return {load_le<double>(p), load_le<double>(p + 8), load_le<double>(p + 16)};
}
glm::vec3 load_vec3(const uint8_t* p) { return {load_le<float>(p), load_le<float>(p + 4), load_le<float>(p + 8)}; }
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

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

uint32_t crc32(const uint8_t* p, size_t n, uint32_t crc) {
  static const auto t = make_crc_tables();
  crc = ~crc;
  while (n >= 8) {
    const uint32_t a = load_le<uint32_t>(p) ^ crc, b = load_le<uint32_t>(p + 4);
    crc = t[7][a & 0xFF] ^ t[6][(a >> 8) & 0xFF] ^ t[5][(a >> 16) & 0xFF] ^ t[4][a >> 24] ^ t[3][b & 0xFF] ^
          t[2][(b >> 8) & 0xFF] ^ t[1][(b >> 16) & 0xFF] ^ t[0][b >> 24];
    p += 8;
    n -= 8;
  }
  while (n--) crc = t[0][(crc ^ *p++) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

uint64_t scan_cache_chunk_bytes(uint32_t count, uint32_t flags) {
  const uint64_t n = count;
  uint64_t bytes = 12 * n + 4 * n + 4 * n;  // positions, point ids, layout ranks
  if (flags & uint32_t(Attribute::Color)) bytes += 4 * n;
  if (flags & uint32_t(Attribute::Intensity)) bytes += 4 * n;
  if (flags & uint32_t(Attribute::Classification)) bytes += pad4(n);
  if (flags & uint32_t(Attribute::Normal)) bytes += 12 * n;
  return bytes;
}

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

void ScanCache::fail(const std::string& reason, int64_t offset) const {
  throw ReadError(file_.path(), reason, offset);
}

ScanCache::ScanCache(const std::string& path) : file_(path, MappedFile::Access::OnDemand) {
  const uint8_t* d = file_.data();
  const uint64_t size = file_.size();
  if (size < 8 || std::memcmp(d, kScanCacheMagic, 8) != 0)
    fail("not a PointNPR scan cache (its first bytes are not \"PNPRSCAN\")", 0);
  if (size < kScanCacheHeaderBytes)
    fail("truncated scan cache: " + std::to_string(size) + " bytes, shorter than its " +
         std::to_string(kScanCacheHeaderBytes) + "-byte header");
  // The version first: another version may lay its header out differently.
  const uint32_t version = load_le<uint32_t>(d + kVersionAt);
  if (version != kScanCacheVersion)
    fail("scan cache version " + std::to_string(version) + ", this PointNPR reads version " +
         std::to_string(kScanCacheVersion) + ": import the scan again to rebuild its cache", kVersionAt);
  if (load_le<uint32_t>(d + kHeaderChecksumAt) != crc32(d, kHeaderChecksumAt))
    fail("damaged scan cache: the header's checksum does not match its bytes", 0);
  const uint64_t file_bytes = load_le<uint64_t>(d + kFileBytesAt);
  if (size < file_bytes)
    fail("truncated scan cache: " + std::to_string(size) + " bytes of " + std::to_string(file_bytes) +
         " (the copy or the write did not finish)");
  if (size > file_bytes)
    fail("scan cache with " + std::to_string(size - file_bytes) + " bytes after its end", int64_t(file_bytes));
  flags_ = load_le<uint32_t>(d + kFlagsAt);
  if (flags_ & ~kKnownFlags) fail("scan cache with unknown attribute flags " + std::to_string(flags_), kFlagsAt);
  const uint32_t chunk_count = load_le<uint32_t>(d + kChunkCountAt);
  points_ = load_le<uint64_t>(d + kPointCountAt);
  bounds_min_ = load_dvec3(d + kBoundsMinAt);
  bounds_max_ = load_dvec3(d + kBoundsMaxAt);
  const uint64_t table_offset = load_le<uint64_t>(d + kTableOffsetAt);
  const uint64_t data_offset = load_le<uint64_t>(d + kDataOffsetAt);
  if (load_le<uint32_t>(d + kHeaderBytesAt) != kScanCacheHeaderBytes || table_offset != kScanCacheHeaderBytes ||
      data_offset != table_offset + uint64_t(kScanCacheTableEntryBytes) * chunk_count || data_offset > file_bytes)
    fail("damaged scan cache: its header's offsets do not describe its chunk table", kTableOffsetAt);
  if (!finite(bounds_min_) || !finite(bounds_max_)) fail("damaged scan cache: non-finite bounds", kBoundsMinAt);
  const uint8_t* table = d + table_offset;
  if (load_le<uint32_t>(d + kTableChecksumAt) != crc32(table, data_offset - table_offset))
    fail("damaged scan cache: the chunk table's checksum does not match its bytes", int64_t(table_offset));

  chunks_.resize(chunk_count);
  uint64_t offset = data_offset, total = 0;
  for (uint32_t i = 0; i < chunk_count; ++i) {
    const uint8_t* e = table + kScanCacheTableEntryBytes * i;
    ScanCacheChunk& c = chunks_[i];
    c.origin = load_dvec3(e);
    c.local_min = load_vec3(e + 24);
    c.local_max = load_vec3(e + 36);
    c.count = load_le<uint32_t>(e + 48);
    c.checksum = load_le<uint32_t>(e + 52);
    c.offset = load_le<uint64_t>(e + 56);
    const int64_t at = int64_t(table_offset + kScanCacheTableEntryBytes * i);
    if (c.count > kScanCacheMaxChunkPoints)
      fail("damaged scan cache: chunk " + std::to_string(i) + " claims " + std::to_string(c.count) + " points", at);
    if (!finite(c.origin) || !finite(glm::dvec3(c.local_min)) || !finite(glm::dvec3(c.local_max)))
      fail("damaged scan cache: chunk " + std::to_string(i) + " has non-finite bounds", at);
    // Chunks follow each other without gaps: nothing can overlap or point outside.
    if (c.offset != offset || file_bytes - offset < scan_cache_chunk_bytes(c.count, flags_))
      fail("damaged scan cache: chunk " + std::to_string(i) + "'s data does not follow the previous one", at);
    offset += scan_cache_chunk_bytes(c.count, flags_);
    total += c.count;
  }
  if (offset != file_bytes || total != points_)
    fail("damaged scan cache: its chunks hold " + std::to_string(total) + " points in " +
         std::to_string(offset) + " bytes, the header says " + std::to_string(points_) + " in " +
         std::to_string(file_bytes));
  file_.release(0, data_offset);  // header and table are copied: nothing of the file stays resident
  verified_ = std::make_unique<std::atomic<uint8_t>[]>(chunk_count);
  for (uint32_t i = 0; i < chunk_count; ++i) verified_[i].store(0);
}

ScanCacheChunkData ScanCache::chunk(size_t i) const {
  if (i >= chunks_.size()) throw Error("scan cache chunk " + std::to_string(i) + " out of range");
  const ScanCacheChunk& c = chunks_[i];
  const uint8_t* p = file_.data() + c.offset;
  const uint64_t bytes = scan_cache_chunk_bytes(c.count, flags_);
  if (!verified_[i].load(std::memory_order_acquire)) {
    if (crc32(p, bytes) != c.checksum)
      fail("damaged scan cache: chunk " + std::to_string(i) + "'s checksum does not match its points",
           int64_t(c.offset));
    verified_[i].store(1, std::memory_order_release);
    file_.release(c.offset, bytes);  // verifying touched all of it; a frame needs only its prefix
  }
  const uint64_t n = c.count;
  ScanCacheChunkData v;
  v.count = c.count;
  v.positions = p;
  p += 12 * n;
  v.point_index = p;
  p += 4 * n;
  v.layout_rank = p;
  p += 4 * n;
  if (has(Attribute::Color)) v.colors = p, p += 4 * n;
  if (has(Attribute::Intensity)) v.intensity = p, p += 4 * n;
  if (has(Attribute::Classification)) v.classification = p, p += pad4(n);
  if (has(Attribute::Normal)) v.normals = p;
  return v;
}

}  // namespace pointnpr::io
