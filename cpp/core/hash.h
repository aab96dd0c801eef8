#pragma once
// lowbias32 (Chris Wellons' integer hash), the same function as the
// shaders' hash_u32 (shaders/common.glsl): the seeded randomness of the
// core (the resolution queue's order, mesh sampling) is the GPU's.
#include <cstdint>

namespace pointnpr {

inline uint32_t hash_u32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

}  // namespace pointnpr
