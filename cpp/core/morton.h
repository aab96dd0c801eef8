#pragma once
// Morton (Z-order) codes: points close in space get close codes, so sorting
// by them lays points out in compact, cache-friendly blocks.
#include <cstdint>

namespace pointnpr {

// Spreads the low 21 bits of v so that three can be interleaved.
inline uint64_t morton_spread_bits(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

// The inverse of morton_spread_bits: every third bit of v, packed.
inline uint64_t morton_compact_bits(uint64_t v) {
  v &= 0x1249249249249249ULL;
  v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3ULL;
  v = (v ^ (v >> 4)) & 0x100f00f00f00f00fULL;
  v = (v ^ (v >> 8)) & 0x1f0000ff0000ffULL;
  v = (v ^ (v >> 16)) & 0x1f00000000ffffULL;
  v = (v ^ (v >> 32)) & 0x1fffffULL;
  return v;
}

// The 63-bit code of three 21-bit cell coordinates.
inline uint64_t morton_code(uint64_t x, uint64_t y, uint64_t z) {
  return morton_spread_bits(x) | morton_spread_bits(y) << 1 | morton_spread_bits(z) << 2;
}

}  // namespace pointnpr
