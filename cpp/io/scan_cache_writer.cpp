// The writer of the scan cache (its reader, io/scan_cache.cpp, needs
// nothing of the renderer: the fuzz target builds it alone).
#include "io/scan_cache_writer.h"

#include <array>
#include <cerrno>
#include <cstring>

#include "core/error.h"
#include "io/scan_cache.h"
#include "io/scan_cache_layout.h"
#include "render/gpu_cloud.h"  // queue_order: the resolution queue's definition

namespace pointnpr::io {

using namespace scan_cache_layout;

ScanCacheFileWriter::ScanCacheFileWriter(const std::string& path, uint32_t flags, size_t chunk_count)
    : path_(path), temp_(path + ".partial"), flags_(flags), chunk_count_(chunk_count) {
  f_ = std::fopen(temp_.c_str(), "wb");
  if (!f_) fail(std::strerror(errno));
  table_.assign(kScanCacheTableEntryBytes * chunk_count, 0);
  offset_ = kScanCacheHeaderBytes + table_.size();
  write(std::vector<uint8_t>(offset_, 0).data(), offset_);  // header and table, filled in by finish()
}

ScanCacheFileWriter::~ScanCacheFileWriter() {
  if (f_) std::fclose(f_);
  if (!committed_) std::remove(temp_.c_str());
}

void ScanCacheFileWriter::fail(const char* why) const {
  throw Error("cannot write the scan cache " + path_ + ": " + why);
}

void ScanCacheFileWriter::write(const void* data, size_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, f_) != bytes) fail(std::strerror(errno));
}

void ScanCacheFileWriter::add(const ScanCacheChunkIn& ch) {
  if (chunks_added_ == chunk_count_) fail("more chunks than announced");
  const uint32_t n = ch.count;
  const uint32_t* q = ch.queue;
  data_.assign(scan_cache_chunk_bytes(n, flags_), 0);
  uint8_t* w = data_.data();
  for (uint32_t i = 0; i < n; ++i) store_vec3(w + 12 * i, ch.positions[q[i]]);
  w += 12 * uint64_t(n);
  for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, ch.point_index[q[i]]);
  w += 4 * uint64_t(n);
  for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, q[i]);
  w += 4 * uint64_t(n);
  if (flags_ & uint32_t(Attribute::Color)) {
    for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, ch.colors[q[i]]);
    w += 4 * uint64_t(n);
  }
  if (flags_ & uint32_t(Attribute::Intensity)) {
    for (uint32_t i = 0; i < n; ++i) store(w + 4 * i, ch.intensity[q[i]]);
    w += 4 * uint64_t(n);
  }
  if (flags_ & uint32_t(Attribute::Classification)) {
    for (uint32_t i = 0; i < n; ++i) w[i] = uint8_t(ch.classification[q[i]]);
    w += pad4(n);
  }
  if (flags_ & uint32_t(Attribute::Normal))
    for (uint32_t i = 0; i < n; ++i) store_vec3(w + 12 * i, ch.normals[q[i]]);
  uint8_t* e = table_.data() + kScanCacheTableEntryBytes * chunks_added_++;
  store_dvec3(e, ch.origin);
  store_vec3(e + 24, ch.local_min);
  store_vec3(e + 36, ch.local_max);
  store(e + 48, n);
  store(e + 52, crc32(data_.data(), data_.size()));
  store(e + 56, offset_);
  write(data_.data(), data_.size());
  offset_ += data_.size();
}

void ScanCacheFileWriter::finish(uint64_t points, const glm::dvec3& bounds_min, const glm::dvec3& bounds_max) {
  if (chunks_added_ != chunk_count_) fail("fewer chunks than announced");
  std::array<uint8_t, kScanCacheHeaderBytes> h{};
  std::memcpy(h.data(), kScanCacheMagic, 8);
  store(h.data() + kVersionAt, kScanCacheVersion);
  store(h.data() + kHeaderBytesAt, uint32_t(kScanCacheHeaderBytes));
  store(h.data() + kFlagsAt, flags_);
  store(h.data() + kChunkCountAt, uint32_t(chunk_count_));
  store(h.data() + kPointCountAt, points);
  store_dvec3(h.data() + kBoundsMinAt, bounds_min);
  store_dvec3(h.data() + kBoundsMaxAt, bounds_max);
  store(h.data() + kTableOffsetAt, uint64_t(kScanCacheHeaderBytes));
  store(h.data() + kDataOffsetAt, uint64_t(kScanCacheHeaderBytes + table_.size()));
  store(h.data() + kFileBytesAt, offset_);
  store(h.data() + kTableChecksumAt, crc32(table_.data(), table_.size()));
  store(h.data() + kHeaderChecksumAt, crc32(h.data(), kHeaderChecksumAt));
  if (std::fseek(f_, 0, SEEK_SET) != 0) fail(std::strerror(errno));
  write(h.data(), h.size());
  write(table_.data(), table_.size());
  const int rc = std::fclose(f_);
  f_ = nullptr;
  if (rc != 0) fail(std::strerror(errno));
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) fail(std::strerror(errno));
  committed_ = true;
}

void write_scan_cache(const std::string& path, const PointCloud& cloud) {
  uint32_t flags = 0;
  for (Attribute a : {Attribute::Color, Attribute::Intensity, Attribute::Classification, Attribute::Normal})
    if (cloud.has(a)) flags |= uint32_t(a);
  for (uint32_t c : cloud.classification())
    if (c > 255) throw Error("cannot write the scan cache " + path + ": classification " + std::to_string(c) +
                             " does not fit the cache's 8 bits");
  const std::vector<uint32_t> order = queue_order(cloud);
  ScanCacheFileWriter out(path, flags, cloud.chunks().size());
  auto at = [](const auto& v, size_t first) { return v.empty() ? nullptr : v.data() + first; };
  for (const PointChunk& ch : cloud.chunks()) {
    ScanCacheChunkIn in;
    in.origin = ch.origin;
    in.local_min = ch.local_min;
    in.local_max = ch.local_max;
    in.count = ch.count;
    in.positions = cloud.local_positions().data() + ch.first;
    in.point_index = cloud.point_index().data() + ch.first;
    in.colors = at(cloud.colors(), ch.first);
    in.intensity = at(cloud.intensity(), ch.first);
    in.classification = at(cloud.classification(), ch.first);
    in.normals = at(cloud.normals(), ch.first);
    in.queue = order.data() + ch.first;
    out.add(in);
  }
  out.finish(cloud.size(), cloud.bounds_min(), cloud.bounds_max());
}

}  // namespace pointnpr::io
