#pragma once
// Read-only view of a whole file: memory-mapped on POSIX, read into memory
// elsewhere. Readers index into data() with explicit bounds checks.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"

namespace pointnpr::io {

class MappedFile {
 public:
  // How the readers go through the bytes: all of them once (mapped
  // populated, read ahead), or a few parts at a time (out-of-core caches:
  // pages are faulted in as they are touched, so memory follows use).
  enum class Access { Sequential, OnDemand };
  // Throws ReadError (naming the path) when the file cannot be opened.
  explicit MappedFile(const std::string& path, Access access = Access::Sequential);
  // A view of bytes owned by the caller (which must outlive this object);
  // `name` stands for the path in messages and extension checks.
  MappedFile(const std::string& name, const uint8_t* data, size_t size)
      : path_(name), data_(data), size_(size) {}
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  // Tells the kernel that bytes [offset, offset + bytes) have been read and
  // will not be needed soon: the whole pages inside leave the process's
  // resident set (a file read again faults them back in from the page
  // cache, so this is only about memory, never about content). Readers that
  // decode a large file front to back call it block by block, so a mapped
  // file does not add its size to the peak memory on top of what is read
  // out of it; an on-demand mapping (a scan cache) stays bounded by what is
  // in use. A no-op for bytes owned by the caller and without mmap.
  void release(size_t offset, size_t bytes) const;

  const uint8_t* data() const { return data_; }
  size_t size() const { return size_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
  void* map_ = nullptr;            // mmap'd region (POSIX)
  std::vector<uint8_t> fallback_;  // whole-file copy where mmap is unavailable
};

// Little-endian loads from unaligned memory (all supported hosts are little-endian).
template <class T>
inline T load_le(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// Big-endian loads (PLY binary_big_endian, PCD never needs it).
template <class T>
inline T load_be(const uint8_t* p) {
  uint8_t b[sizeof(T)];
  for (size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// `s` with bytes outside printable ASCII written as \xNN, cut to `max`
// characters: error messages quote file contents, which may be binary.
inline std::string printable(std::string_view s, size_t max = 2000) {
  static const char* hex = "0123456789abcdef";
  std::string r;
  for (unsigned char c : s) {
    if (r.size() >= max) {
      r += "...";
      break;
    }
    if (c >= 0x20 && c < 0x7F) {
      r += static_cast<char>(c);
    } else {
      r += "\\x";
      r += hex[c >> 4];
      r += hex[c & 15];
    }
  }
  return r;
}

// Double to float without undefined behaviour: values beyond float's range
// become +-inf (a file may hold doubles too large for a float attribute).
inline float narrow_float(double v) {
  constexpr double kMax = std::numeric_limits<float>::max();
  if (v > kMax) return std::numeric_limits<float>::infinity();
  if (v < -kMax) return -std::numeric_limits<float>::infinity();
  return static_cast<float>(v);
}

// Lower-cased extension including the dot (".las"), or "" if none.
std::string file_extension(const std::string& path);

// What every reader holds: the file's bytes (d_, size_) and a way to fail
// that names the file.
class ReaderBase {
 public:
  explicit ReaderBase(const std::string& path)
      : path_(path), file_(path), d_(file_.data()), size_(file_.size()) {}
  ReaderBase(const std::string& name, const uint8_t* data, size_t size)
      : path_(name), file_(name, data, size), d_(file_.data()), size_(file_.size()) {}

 protected:
  [[noreturn]] void fail(const std::string& reason, int64_t offset = -1) const {
    throw ReadError(path_, printable(reason), offset);
  }
  std::string path_;
  MappedFile file_;
  const uint8_t* d_;
  size_t size_;
};

}  // namespace pointnpr::io
