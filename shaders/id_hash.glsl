// The object-space marks' randomness: an integer hash (lowbias32, Wellons)
// of stable point ids (the same as GpuCloud's queue_hash), so every choice
// is the same in every frame and process. Shared with the native backends
// (the subset of cpp/core/glsl.h).
#ifndef ID_HASH_GLSL
#define ID_HASH_GLSL
uint id_hash(uint x) {
  x ^= x >> 16; x *= 0x7feb352du;
  x ^= x >> 15; x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// Uniform in [0, 1) for a point id, a salt (one per decision) and a seed.
float id_rand(uint id, uint salt, uint seed) {
  return float(id_hash(id ^ id_hash(salt * 0x9e3779b9u + seed * 0x85ebca6bu)) >> 8) * (1.0f / 16777216.0f);
}

// Uniform in [0, 1) at an integer lattice corner (a float holding an
// integer; negative ones wrap as two's complement) for a hashed seed.
float lattice_rand(uint base, float x, float y) {
  return float(id_hash(base ^ id_hash(uint(int(x)) * 73856093u ^ uint(int(y)) * 19349663u)) >> 8) / 16777216.0f;
}

// Value noise in a mark's own coordinates, seeded per mark: grain that
// moves with the stroke.
float id_value_noise(vec2 q, uint seed) {
  vec2 i = floor(q), f = fract(q);
  vec2 w = f * f * (3.0f - 2.0f * f);
  uint base = id_hash(seed);
  float a = lattice_rand(base, i.x, i.y);
  float b = lattice_rand(base, i.x + 1.0f, i.y);
  float c = lattice_rand(base, i.x, i.y + 1.0f);
  float d = lattice_rand(base, i.x + 1.0f, i.y + 1.0f);
  return mix(mix(a, b, w.x), mix(c, d, w.x), w.y);
}
#endif
