// Per-point data every mark reads: positions (binding 0), the colour
// attribute (binding 1) and normals (binding 2, snorm8 x3), with the chunk's
// transform. Set by bind_chunk() (cpp/render/mark.cpp).
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Attribute { uint attribute_u[]; };
layout(std430, binding = 2) readonly buffer Normals { uint normals_u[]; };

uniform mat4 u_view_from_chunk;  // composed in double on the CPU, then cast
uniform mat3 u_normal_matrix;    // view from chunk, for normals
uniform uint u_first;
uniform uint u_count;
uniform uint u_key_base;
uniform int u_color_source;      // 0 rgb, 1 intensity, 2 classification, 3 constant (auto resolved on the CPU)
uniform float u_intensity_scale;
uniform vec4 u_constant_color;

// ASPRS LAS classes 0-18 (display sRGB); others fall back to gray.
const vec3 CLASS_COLORS[19] = vec3[](
  vec3(0.60), vec3(0.70), vec3(0.63, 0.48, 0.33), vec3(0.56, 0.80, 0.45), vec3(0.36, 0.68, 0.30),
  vec3(0.16, 0.47, 0.20), vec3(0.85, 0.42, 0.32), vec3(0.90, 0.10, 0.60), vec3(0.90, 0.85, 0.20),
  vec3(0.25, 0.50, 0.90), vec3(0.55, 0.55, 0.60), vec3(0.35, 0.35, 0.38), vec3(0.80, 0.80, 0.80),
  vec3(0.95, 0.75, 0.20), vec3(0.95, 0.55, 0.10), vec3(0.70, 0.30, 0.90), vec3(0.50, 0.90, 0.90),
  vec3(0.60, 0.40, 0.25), vec3(0.95, 0.20, 0.20));

vec3 point_position(uint index) {
  return vec3(positions[3u * index], positions[3u * index + 1u], positions[3u * index + 2u]);
}

vec4 source_color(uint index) {
  if (u_color_source == 0) return vec4(unpackUnorm4x8(attribute_u[index]).rgb, 1.0);
  if (u_color_source == 1) return vec4(vec3(clamp(uintBitsToFloat(attribute_u[index]) * u_intensity_scale, 0.0, 1.0)), 1.0);
  if (u_color_source == 2) {
    uint c = attribute_u[index];
    return vec4(c < 19u ? CLASS_COLORS[c] : vec3(0.5), 1.0);
  }
  return vec4(u_constant_color.rgb, 1.0);
}

// View-space unit normal, or vec3(0) where the point has no usable normal
// (packed as zero: degenerate neighbourhoods, non-finite input).
vec3 view_normal(uint index) {
  vec3 n = u_normal_matrix * unpackSnorm4x8(normals_u[index]).xyz;
  float len = length(n);
  return len > 1e-3 ? n / len : vec3(0.0);
}
