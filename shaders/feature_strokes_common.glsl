// Shared by the feature_strokes mark's passes (cpp/marks/feature_strokes.cpp).
struct Record {
  vec4 center_kind;  // view-space centre, class (0 directional, 1 non-directional, 2 dithering)
  vec4 dir_length;   // view-space unit 3D direction (directional) or 0, length (px)
  vec4 color;        // display sRGB, opacity
  uint point_id;
  uint primitive;    // 1 point sprite, 2 line segment, 3 textured stroke
  float width;       // px
  float pad;
};
layout(std430, binding = 7) buffer Records { Record records[]; };

// Integer hash (lowbias32, Wellons), fed with point ids: the only source of
// randomness (the same as GpuCloud's queue_hash).
uint hash_u32(uint x) {
  x ^= x >> 16; x *= 0x7feb352du;
  x ^= x >> 15; x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
float hash01(uint id, uint salt, uint seed) {
  return float(hash_u32(id ^ hash_u32(salt * 0x9e3779b9u + seed * 0x85ebca6bu)) >> 8) * (1.0 / 16777216.0);
}
