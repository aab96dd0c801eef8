// The object-space marks' randomness: an integer hash (lowbias32, Wellons)
// of stable point ids (the same as GpuCloud's queue_hash), so every choice
// is the same in every frame and process.
uint id_hash(uint x) {
  x ^= x >> 16; x *= 0x7feb352du;
  x ^= x >> 15; x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// Uniform in [0, 1) for a point id, a salt (one per decision) and a seed.
float id_rand(uint id, uint salt, uint seed) {
  return float(id_hash(id ^ id_hash(salt * 0x9e3779b9u + seed * 0x85ebca6bu)) >> 8) * (1.0 / 16777216.0);
}

// Value noise in a mark's own coordinates, seeded per mark: grain that
// moves with the stroke.
float id_value_noise(vec2 q, uint seed) {
  vec2 i = floor(q), f = fract(q);
  vec2 w = f * f * (3.0 - 2.0 * f);
  uint base = id_hash(seed);
  float a = float(id_hash(base ^ id_hash(uint(i.x) * 73856093u ^ uint(i.y) * 19349663u)) >> 8) / 16777216.0;
  float b = float(id_hash(base ^ id_hash(uint(i.x + 1.0) * 73856093u ^ uint(i.y) * 19349663u)) >> 8) / 16777216.0;
  float c = float(id_hash(base ^ id_hash(uint(i.x) * 73856093u ^ uint(i.y + 1.0) * 19349663u)) >> 8) / 16777216.0;
  float d = float(id_hash(base ^ id_hash(uint(i.x + 1.0) * 73856093u ^ uint(i.y + 1.0) * 19349663u)) >> 8) / 16777216.0;
  return mix(mix(a, b, w.x), mix(c, d, w.x), w.y);
}
