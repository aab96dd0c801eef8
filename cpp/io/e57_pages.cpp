#include "io/e57_pages.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "io/mapped_file.h"

namespace pointnpr::e57 {

namespace {

// Slicing-by-8 tables: eight bytes per step, no intrinsics.
struct Crc32cTables {
  std::array<std::array<uint32_t, 256>, 8> t{};
  Crc32cTables() {
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ ((c & 1) ? 0x82F63B78u : 0u);
      t[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; ++i)
      for (int s = 1; s < 8; ++s) t[s][i] = (t[s - 1][i] >> 8) ^ t[0][t[s - 1][i] & 0xFF];
  }
};

const Crc32cTables& tables() {
  static const Crc32cTables tables;
  return tables;
}

std::string hex32(uint32_t v) {
  static const char* digits = "0123456789abcdef";
  std::string s = "0x";
  for (int i = 7; i >= 0; --i) s += digits[(v >> (4 * i)) & 15];
  return s;
}

}  // namespace

uint32_t crc32c(const uint8_t* p, size_t n) {
  const auto& t = tables().t;
  uint32_t c = 0xFFFFFFFFu;
  while (n >= 8) {
    uint64_t w = io::load_le<uint64_t>(p) ^ c;
    c = t[7][w & 0xFF] ^ t[6][(w >> 8) & 0xFF] ^ t[5][(w >> 16) & 0xFF] ^ t[4][(w >> 24) & 0xFF] ^
        t[3][(w >> 32) & 0xFF] ^ t[2][(w >> 40) & 0xFF] ^ t[1][(w >> 48) & 0xFF] ^ t[0][w >> 56];
    p += 8;
    n -= 8;
  }
  while (n--) c = (c >> 8) ^ t[0][(c ^ *p++) & 0xFF];
  return c ^ 0xFFFFFFFFu;
}

PagedFile::PagedFile(std::string name, const uint8_t* data, size_t size)
    : name_(std::move(name)), data_(data), size_(size) {
  if (size_ < kPageSize)
    fail("file too short for an E57 file (" + std::to_string(size_) + " bytes; the first page alone is 1024)");
  if (std::memcmp(data_, "ASTM-E57", 8) != 0) fail("not an E57 file (no ASTM-E57 signature)", 0);
  header_.version_major = io::load_le<uint32_t>(data_ + 8);
  header_.version_minor = io::load_le<uint32_t>(data_ + 12);
  header_.physical_length = io::load_le<uint64_t>(data_ + 16);
  header_.xml_physical_offset = io::load_le<uint64_t>(data_ + 24);
  header_.xml_logical_length = io::load_le<uint64_t>(data_ + 32);
  header_.page_size = io::load_le<uint64_t>(data_ + 40);
  if (header_.version_major != 1)
    fail("unsupported E57 version " + std::to_string(header_.version_major) + "." +
             std::to_string(header_.version_minor) + " (this reader knows 1.x)", 8);
  if (header_.page_size != kPageSize)
    fail("page size " + std::to_string(header_.page_size) + " is not 1024", 40);
  if (header_.physical_length != size_)
    fail("the header gives a length of " + std::to_string(header_.physical_length) + " bytes but the file has " +
             std::to_string(size_) + (header_.physical_length > size_ ? " (truncated)" : ""), 16);
  if (size_ % kPageSize != 0)
    fail("file length " + std::to_string(size_) + " is not a whole number of 1024-byte pages", 16);
  const uint64_t xml_begin = to_logical(header_.xml_physical_offset);
  if (header_.xml_logical_length == 0 || xml_begin > logical_size() ||
      header_.xml_logical_length > logical_size() - xml_begin)
    fail("the XML section (offset " + std::to_string(header_.xml_physical_offset) + ", " +
             std::to_string(header_.xml_logical_length) + " bytes) lies outside the file", 24);
}

void PagedFile::verify_checksums() const {
  // Pages are checked in parallel blocks; the lowest bad page is reported,
  // whatever the thread timing.
  const uint64_t pages = size_ / kPageSize;
  std::atomic<uint64_t> first_bad{pages};
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, pages, 256), [&](const tbb::blocked_range<uint64_t>& r) {
    for (uint64_t page = r.begin(); page < r.end() && page < first_bad.load(std::memory_order_relaxed); ++page) {
      const uint8_t* p = data_ + page * kPageSize;
      if (io::load_be<uint32_t>(p + kPageContent) != crc32c(p, kPageContent)) {
        uint64_t seen = first_bad.load();
        while (page < seen && !first_bad.compare_exchange_weak(seen, page)) {
        }
        return;
      }
    }
  });
  if (first_bad.load() < pages) {
    const uint64_t page = first_bad.load();
    const uint8_t* p = data_ + page * kPageSize;
    const uint32_t stored = io::load_be<uint32_t>(p + kPageContent);
    const uint32_t computed = crc32c(p, kPageContent);
    fail("CRC-32C mismatch in page " + std::to_string(page) + " (bytes " + std::to_string(page * kPageSize) +
               "-" + std::to_string(page * kPageSize + kPageSize - 1) + "): stored " + hex32(stored) +
               ", computed " + hex32(computed),
           static_cast<int64_t>(page * kPageSize + kPageContent));
  }
}

uint64_t PagedFile::to_logical(uint64_t physical) const {
  if (physical % kPageSize >= kPageContent)
    fail("offset " + std::to_string(physical) + " points into a page's checksum", static_cast<int64_t>(physical));
  if (physical >= size_)
    fail("offset " + std::to_string(physical) + " lies beyond the end of the file (" + std::to_string(size_) +
             " bytes)", static_cast<int64_t>(physical));
  return physical / kPageSize * kPageContent + physical % kPageSize;
}

void PagedFile::copy(uint64_t logical, size_t n, uint8_t* dst) const {
  if (logical > logical_size() || n > logical_size() - logical)
    fail(std::to_string(n) + " bytes at logical offset " + std::to_string(logical) + " run past the end of the file",
         static_cast<int64_t>(std::min<uint64_t>(to_physical(logical), size_)));
  while (n > 0) {
    const uint64_t in_page = logical % kPageContent;
    const size_t take = static_cast<size_t>(std::min<uint64_t>(n, kPageContent - in_page));
    std::memcpy(dst, data_ + to_physical(logical), take);
    dst += take;
    logical += take;
    n -= take;
  }
}

void PagedFile::fail(const std::string& reason, int64_t physical_offset) const {
  throw ReadError(name_, io::printable(reason), physical_offset);
}

}  // namespace pointnpr::e57
