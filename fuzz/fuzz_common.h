#pragma once
// Shared body of the reader fuzz targets: read the bytes from memory; a
// ReadError is the expected outcome for most inputs, anything else (another
// exception, a crash, a sanitizer report, an inconsistent result) is a bug.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <variant>

#include "core/error.h"
#include "io/readers.h"

namespace pointnpr::fuzz {

// The result must be self-consistent: every attribute has one row per point.
inline void check(const PointData& d) {
  if (d.positions.size() % 3 != 0) std::abort();
  const size_t n = d.num_points();
  for (const PointAttribute& a : d.attributes) {
    const size_t values = std::visit([](const auto& v) { return v.size(); }, a.values);
    if (a.components < 1 || values != n * static_cast<size_t>(a.components)) std::abort();
  }
}

template <class Read>
int run(const uint8_t* data, size_t size, const char* name, Read read) {
  try {
    check(read(data, size, std::string(name)));
  } catch (const ReadError&) {
  }
  return 0;
}

}  // namespace pointnpr::fuzz
