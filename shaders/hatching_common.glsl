// Shared by the hatching mark's passes (cpp/marks/hatching.cpp).
struct Stroke {
  vec4 center_alpha;  // view-space centre, opacity (<= 0: no stroke)
  vec4 d1_length;     // unit direction of the first line, length (scene units)
  vec4 n_width;       // unit normal, width (scene units; negative: crossed)
  vec3 color;         // display sRGB
  uint point_id;
};
layout(std430, binding = 7) buffer Strokes { Stroke strokes[]; };

// Integer hash (lowbias32, Wellons): the only source of randomness, fed
// with point ids, so every choice is the same in every frame.
uint hash_u32(uint x) {
  x ^= x >> 16; x *= 0x7feb352du;
  x ^= x >> 15; x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
float hash01(uint id, uint salt, uint seed) {
  return float(hash_u32(id ^ hash_u32(salt * 0x9e3779b9u + seed * 0x85ebca6bu)) >> 8) * (1.0 / 16777216.0);
}
