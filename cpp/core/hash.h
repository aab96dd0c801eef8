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

// Uniform in [0, 1) for a point id, a salt (one per decision) and a seed:
// the shaders' id_rand (shaders/id_hash.glsl), for the native paths.
inline float id_rand(uint32_t id, uint32_t salt, uint32_t seed) {
  return float(hash_u32(id ^ hash_u32(salt * 0x9e3779b9u + seed * 0x85ebca6bu)) >> 8) * (1.0f / 16777216.0f);
}

}  // namespace pointnpr
