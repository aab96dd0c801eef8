#include "shared_kernels.glsl"
#include "point_color.glsl"

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

vec3 point_position(uint index) {
  return vec3(positions[3u * index], positions[3u * index + 1u], positions[3u * index + 2u]);
}

vec4 source_color(uint index) {
  return attribute_color(u_color_source, attribute_u[index], u_intensity_scale, u_constant_color);
}

// View-space unit normal, or vec3(0) where the point has no usable normal
// (packed as zero: degenerate neighbourhoods, non-finite input).
vec3 view_normal(uint index) { return unit_or_zero(u_normal_matrix * unpackSnorm4x8(normals_u[index]).xyz); }
