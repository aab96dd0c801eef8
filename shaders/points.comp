// Compute rasterizer (after Schuetz et al. 2021): visibility by atomicMin on
// linear depth, then a deterministic tie break on the point key, then colour.
// With 64-bit atomics depth and key are packed and resolved in one pass.
// variants: PASS_DEPTH | PASS_KEY | PASS_COLOR | INT64_ATOMICS PASS_DEPTH | INT64_ATOMICS PASS_COLOR
#ifdef INT64_ATOMICS
#extension GL_ARB_gpu_shader_int64 : require
#extension GL_NV_shader_atomic_int64 : require
#endif
#include "common.glsl"
#include "points.glsl"

layout(local_size_x = 128) in;
#ifdef INT64_ATOMICS
layout(std430, binding = 4) buffer DepthKeys { uint64_t depth_keys[]; };
#else
layout(std430, binding = 4) buffer Depths { uint depths[]; };
layout(std430, binding = 5) buffer Keys { uint keys[]; };
#endif
layout(std430, binding = 3) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices (u_queue)
uniform int u_image_width;  // the images' (a tile's), for the per-pixel buffers
uniform int u_queue;  // 1: the i-th invocation draws the chunk's i-th point of the resolution queue
layout(rgba32f, binding = 0) uniform writeonly image2D u_color_out;
layout(r32f, binding = 1) uniform writeonly image2D u_depth_out;
layout(r32f, binding = 2) uniform writeonly image2D u_spacing_out;  // with u_write_spacing

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  uint local = u_queue != 0 ? queue_order[u_first + i] : i;
  uint index = u_first + local;
  Splat s = project_point(index);
  if (!s.visible) return;
  // The tile's pixels: the frame's less the integer origin (exact for every
  // splat that reaches the tile), so coverage is the frame's bit for bit.
  s.center -= vec2(u_origin);
  float r = 0.5 * s.diameter;
  ivec2 lo = max(ivec2(floor(s.center - r)), u_clip_rect.xy);
  ivec2 hi = min(ivec2(ceil(s.center + r)), u_clip_rect.zw - 1);
  uint depth_bits = floatBitsToUint(s.depth);  // positive floats order as uints
  uint key = u_key_base + local;
#ifdef PASS_COLOR
  vec4 color = point_color(index);
  float spacing = point_spacing(index);
#endif
  for (int y = lo.y; y <= hi.y; ++y) {
    for (int x = lo.x; x <= hi.x; ++x) {
      if (!covers(vec2(x, y) + 0.5 - s.center, s.diameter)) continue;
      uint pixel = uint(y) * uint(u_image_width) + uint(x);
#ifdef INT64_ATOMICS
      uint64_t packed = packUint2x32(uvec2(key, depth_bits));
#ifdef PASS_DEPTH
      atomicMin(depth_keys[pixel], packed);
#else
      if (depth_keys[pixel] == packed) {
        imageStore(u_color_out, ivec2(x, y), color);
        imageStore(u_depth_out, ivec2(x, y), vec4(s.depth));
        if (u_write_spacing != 0) imageStore(u_spacing_out, ivec2(x, y), vec4(spacing));
      }
#endif
#else
#ifdef PASS_DEPTH
      atomicMin(depths[pixel], depth_bits);
#elif defined(PASS_KEY)
      if (depths[pixel] == depth_bits) atomicMin(keys[pixel], key);
#else
      if (keys[pixel] == key) {
        imageStore(u_color_out, ivec2(x, y), color);
        imageStore(u_depth_out, ivec2(x, y), vec4(s.depth));
        if (u_write_spacing != 0) imageStore(u_spacing_out, ivec2(x, y), vec4(spacing));
      }
#endif
#endif
    }
  }
}
