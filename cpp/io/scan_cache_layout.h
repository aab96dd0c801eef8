#pragma once
// Byte layout of the scan cache shared by its reader (io/scan_cache.cpp)
// and writer (io/scan_cache_writer.cpp); docs/io.md#scan-cache.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>

namespace pointnpr::io::scan_cache_layout {

// Byte offsets of the header's fields (docs/io.md#scan-cache).
inline constexpr size_t kVersionAt = 8, kHeaderBytesAt = 12, kFlagsAt = 16, kChunkCountAt = 20, kPointCountAt = 24,
                 kBoundsMinAt = 32, kBoundsMaxAt = 56, kTableOffsetAt = 80, kDataOffsetAt = 88, kFileBytesAt = 96,
                 kTableChecksumAt = 104, kHeaderChecksumAt = 124;

inline uint64_t pad4(uint64_t n) { return (n + 3) & ~uint64_t(3); }

template <class T>
inline void store(uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}

inline void store_dvec3(uint8_t* p, const glm::dvec3& v) {
  for (int c = 0; c < 3; ++c) store(p + 8 * c, v[c]);
}
inline void store_vec3(uint8_t* p, const glm::vec3& v) {
  for (int c = 0; c < 3; ++c) store(p + 4 * c, v[c]);
}
}  // namespace pointnpr::io::scan_cache_layout
