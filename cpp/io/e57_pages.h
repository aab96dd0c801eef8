#pragma once
// ASTM E2807 (E57) physical layer: the 48-byte file header and the 1024-byte
// pages, each 1020 bytes of content and a CRC-32C. Offsets in the XML
// (fileOffset) and the header are physical; lengths inside binary sections
// are logical (content bytes, the CRCs left out).
#include <cstddef>
#include <cstdint>
#include <string>

namespace pointnpr::e57 {

constexpr uint64_t kPageSize = 1024;
constexpr uint64_t kPageContent = 1020;
constexpr size_t kFileHeaderSize = 48;

// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), as E57 pages carry it.
uint32_t crc32c(const uint8_t* data, size_t size);

struct FileHeader {
  uint32_t version_major = 0;
  uint32_t version_minor = 0;
  uint64_t physical_length = 0;
  uint64_t xml_physical_offset = 0;
  uint64_t xml_logical_length = 0;
  uint64_t page_size = 0;
};

// The file's bytes seen through its pages. Every method that can meet bad
// bytes throws ReadError naming `name` and the physical offset.
class PagedFile {
 public:
  PagedFile(std::string name, const uint8_t* data, size_t size);

  // Parses and checks the header (signature, version, length, page size).
  const FileHeader& header() const { return header_; }
  // Checks every page's CRC-32C; a mismatch names the page and its offset.
  void verify_checksums() const;

  // Logical offset of physical offset `physical` (which must not point into a CRC).
  uint64_t to_logical(uint64_t physical) const;
  static uint64_t to_physical(uint64_t logical) {
    return logical / kPageContent * kPageSize + logical % kPageContent;
  }
  // Logical bytes of the file: the content of all its pages.
  uint64_t logical_size() const { return size_ / kPageSize * kPageContent; }
  // Copies logical bytes [logical, logical + n) into dst, across pages.
  void copy(uint64_t logical, size_t n, uint8_t* dst) const;

  [[noreturn]] void fail(const std::string& reason, int64_t physical_offset = -1) const;
  const std::string& name() const { return name_; }
  size_t size() const { return size_; }

 private:
  std::string name_;
  const uint8_t* data_;
  size_t size_;
  FileHeader header_;
};

}  // namespace pointnpr::e57
