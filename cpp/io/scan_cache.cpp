#include "io/scan_cache.h"

#include <array>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "io/scan_cache_layout.h"

namespace pointnpr::io {

using namespace scan_cache_layout;

namespace {

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

glm::dvec3 load_dvec3(const uint8_t* p) {
  return {load_le<double>(p), load_le<double>(p + 8), load_le<double>(p + 16)};
}
glm::vec3 load_vec3(const uint8_t* p) { return {load_le<float>(p), load_le<float>(p + 4), load_le<float>(p + 8)}; }
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

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

void ScanCache::fail(const std::string& reason, int64_t offset) const {
  throw ReadError(file_.path(), reason, offset);
}

ScanCache::ScanCache(const std::string& path) : file_(path, MappedFile::Access::OnDemand) { validate(); }

ScanCache::ScanCache(const std::string& name, const uint8_t* data, size_t size) : file_(name, data, size) {
  validate();
}

void ScanCache::validate() {
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
    // The layout ranks must be a permutation (streaming indexes by them):
    // checked once, with the checksum, against a file that lies consistently.
    std::vector<uint8_t> seen(c.count, 0);
    const uint8_t* ranks = p + 16 * uint64_t(c.count);
    for (uint32_t k = 0; k < c.count; ++k) {
      const uint32_t r = load_le<uint32_t>(ranks + 4 * uint64_t(k));
      if (r >= c.count || seen[r])
        fail("damaged scan cache: chunk " + std::to_string(i) + "'s layout ranks are not a permutation",
             int64_t(c.offset + 16 * uint64_t(c.count) + 4 * uint64_t(k)));
      seen[r] = 1;
    }
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
