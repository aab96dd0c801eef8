#pragma once
// A stable radix sort of 64-bit keys by their high 32 bits, a byte a pass,
// skipping the bytes every key shares. Keys built as (sort bits << 32 |
// index) in ascending index come out in std::sort's order, several times
// faster for a few thousand keys (a screen bin's splats by depth).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace pointnpr {

// Sorts `keys` by their high 32 bits, keeping the order of equal ones;
// `scratch` is reused storage.
inline void stable_sort_by_high_words(std::vector<uint64_t>& keys, std::vector<uint64_t>& scratch) {
  const size_t n = keys.size();
  if (n < 256 || n > UINT32_MAX) {  // (fewer: the passes' counts cost more than they save; more: counts overflow)
    std::stable_sort(keys.begin(), keys.end(), [](uint64_t a, uint64_t b) { return a >> 32 < b >> 32; });
    return;
  }
  scratch.resize(n);
  uint32_t counts[4][256] = {};
  for (const uint64_t k : keys)
    for (int b = 0; b < 4; ++b) ++counts[b][(k >> (32 + 8 * b)) & 255];
  uint64_t *from = keys.data(), *to = scratch.data();
  for (int b = 0; b < 4; ++b) {
    const int shift = 32 + 8 * b;
    if (counts[b][(from[0] >> shift) & 255] == n) continue;  // one byte for all
    uint32_t at[256];
    uint32_t sum = 0;
    for (int d = 0; d < 256; ++d) at[d] = sum, sum += counts[b][d];
    for (size_t i = 0; i < n; ++i) to[at[(from[i] >> shift) & 255]++] = from[i];
    std::swap(from, to);
  }
  if (from != keys.data()) std::copy(from, from + n, keys.data());
}

}  // namespace pointnpr
