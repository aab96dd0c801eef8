// Per-point setup shared by the compute rasterizer and the GL_POINTS path.
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Attribute { uint attribute_u[]; };
layout(std430, binding = 2) readonly buffer Normals { uint normals_u[]; };  // snorm8 x3

uniform mat4 u_view_from_chunk;  // composed in double on the CPU, then cast
uniform mat4 u_projection;
uniform uint u_first;
uniform uint u_count;
uniform uint u_key_base;
uniform ivec2 u_size;
uniform float u_near;
uniform float u_far;
uniform int u_ortho;
uniform int u_size_mode;      // 0 pixels, 1 world
uniform float u_point_size;
uniform float u_world_size;
uniform float u_px_per_unit;  // pixels per scene unit at view depth 1
uniform float u_max_size;
uniform vec4 u_constant_color;
uniform int u_color_source;   // 0 rgb, 1 intensity, 2 classification, 3 constant
uniform float u_intensity_scale;
uniform ivec4 u_clip_rect;
uniform int u_shading;           // 0 none, 1 diffuse
uniform float u_shading_strength;
uniform vec3 u_light_dir;        // towards the light, view space
uniform mat3 u_normal_matrix;    // view from chunk, for normals

// ASPRS LAS classes 0-18 (display sRGB); others fall back to gray.
const vec3 CLASS_COLORS[19] = vec3[](
  vec3(0.60), vec3(0.70), vec3(0.63, 0.48, 0.33), vec3(0.56, 0.80, 0.45), vec3(0.36, 0.68, 0.30),
  vec3(0.16, 0.47, 0.20), vec3(0.85, 0.42, 0.32), vec3(0.90, 0.10, 0.60), vec3(0.90, 0.85, 0.20),
  vec3(0.25, 0.50, 0.90), vec3(0.55, 0.55, 0.60), vec3(0.35, 0.35, 0.38), vec3(0.80, 0.80, 0.80),
  vec3(0.95, 0.75, 0.20), vec3(0.95, 0.55, 0.10), vec3(0.70, 0.30, 0.90), vec3(0.50, 0.90, 0.90),
  vec3(0.60, 0.40, 0.25), vec3(0.95, 0.20, 0.20));

struct Splat {
  vec2 center;     // window coordinates (pixels)
  float depth;     // linear view depth
  float diameter;  // pixels
  bool visible;
};

Splat project_point(uint index) {
  Splat s;
  vec3 p = vec3(positions[3u * index], positions[3u * index + 1u], positions[3u * index + 2u]);
  vec4 v = u_view_from_chunk * vec4(p, 1.0);
  s.depth = -v.z;
  s.visible = s.depth >= u_near && s.depth <= u_far;
  vec4 clip = u_projection * v;
  s.center = (clip.xy / clip.w * 0.5 + 0.5) * vec2(u_size);
  float w = u_ortho != 0 ? 1.0 : s.depth;
  s.diameter = u_size_mode == 0 ? u_point_size : clamp(u_world_size * u_px_per_unit / w, 1.0, u_max_size);
  return s;
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

vec4 point_color(uint index) {
  vec4 c = source_color(index);
  if (u_shading != 0) {
    vec3 n = u_normal_matrix * unpackSnorm4x8(normals_u[index]).xyz;
    float len = length(n);
    // Two-sided: estimated normals need not face the camera.
    float lambert = len > 0.0 ? abs(dot(n / len, u_light_dir)) : 1.0;
    c.rgb *= 1.0 - u_shading_strength * (1.0 - lambert);
  }
  return c;
}

// Coverage rule shared by both rasterizers: pixel centres within the disk
// of the splat; below 2 px, within its square (as GL point sprites do).
bool covers(vec2 offset, float diameter) {
  float r = 0.5 * diameter;
  if (diameter < 2.0) return abs(offset.x) <= r && abs(offset.y) <= r;
  return dot(offset, offset) <= r * r;
}
