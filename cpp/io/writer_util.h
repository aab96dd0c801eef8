#pragma once
// Shared by the writers: checked output file, attribute access by index.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "io/point_data.h"

namespace pointnpr::io {

// A file opened for writing; removed again unless commit() is called, so a
// failed write never leaves a partial file behind.
class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path) {
    f_ = std::fopen(path.c_str(), "wb");
    if (!f_) fail("cannot open the file for writing");
    std::setvbuf(f_, nullptr, _IOFBF, 1 << 20);
  }
  ~OutputFile() {
    if (f_) {
      std::fclose(f_);
      std::remove(path_.c_str());
    }
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void write(const void* p, size_t n) {
    if (n > 0 && std::fwrite(p, 1, n, f_) != n) fail("write failed (disk full?)");
  }
  void write(const std::string& s) { write(s.data(), s.size()); }
  void commit() {
    std::FILE* f = f_;
    f_ = nullptr;
    if (std::fclose(f) != 0) {
      std::remove(path_.c_str());
      fail("write failed when closing the file (disk full?)");
    }
  }
  [[noreturn]] void fail(const std::string& reason) const {
    throw Error(path_ + ": " + reason);
  }

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
};

// Checks that positions and attributes have consistent sizes.
inline void check_point_data(const std::string& path, const PointData& d) {
  if (d.positions.size() % 3 != 0)
    throw Error(path + ": positions hold " + std::to_string(d.positions.size()) +
                " values, not a multiple of 3");
  const size_t n = d.num_points();
  for (size_t i = 0; i < n * 3; ++i)
    if (!std::isfinite(d.positions[i]))
      throw Error(path + ": point " + std::to_string(i / 3) +
                  " has a non-finite coordinate; remove such points before writing");
  for (const PointAttribute& a : d.attributes) {
    const size_t values = std::visit([](const auto& v) { return v.size(); }, a.values);
    if (a.components < 1 || values != n * static_cast<size_t>(a.components))
      throw Error(path + ": attribute '" + a.name + "' has " + std::to_string(values) +
                  " values for " + std::to_string(n) + " points of " +
                  std::to_string(a.components) + " components");
  }
}

// Element k of an attribute as a double.
inline double value_as_double(const PointAttribute& a, size_t k) {
  return std::visit([k](const auto& v) { return static_cast<double>(v[k]); }, a.values);
}

template <class T>
constexpr bool is_64bit_integer = std::is_integral_v<T> && sizeof(T) == 8;

}  // namespace pointnpr::io
