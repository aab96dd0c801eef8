// A point's colour and its diffuse light, written once for the shaders
// (point_attributes.glsl) and the native backends (render/point_color.h),
// in the common subset of cpp/core/glsl.h.
#ifndef POINT_COLOR_GLSL
#define POINT_COLOR_GLSL

// ASPRS LAS classes 0-18 (display sRGB); other classes gray.
vec3 class_color(uint c) {
  switch (c) {
    case 0u: return vec3(0.60f);
    case 1u: return vec3(0.70f);
    case 2u: return vec3(0.63f, 0.48f, 0.33f);
    case 3u: return vec3(0.56f, 0.80f, 0.45f);
    case 4u: return vec3(0.36f, 0.68f, 0.30f);
    case 5u: return vec3(0.16f, 0.47f, 0.20f);
    case 6u: return vec3(0.85f, 0.42f, 0.32f);
    case 7u: return vec3(0.90f, 0.10f, 0.60f);
    case 8u: return vec3(0.90f, 0.85f, 0.20f);
    case 9u: return vec3(0.25f, 0.50f, 0.90f);
    case 10u: return vec3(0.55f, 0.55f, 0.60f);
    case 11u: return vec3(0.35f, 0.35f, 0.38f);
    case 12u: return vec3(0.80f);
    case 13u: return vec3(0.95f, 0.75f, 0.20f);
    case 14u: return vec3(0.95f, 0.55f, 0.10f);
    case 15u: return vec3(0.70f, 0.30f, 0.90f);
    case 16u: return vec3(0.50f, 0.90f, 0.90f);
    case 17u: return vec3(0.60f, 0.40f, 0.25f);
    case 18u: return vec3(0.95f, 0.20f, 0.20f);
    default: return vec3(0.5f);
  }
}

// The colour of a point's 32-bit attribute under a colour source (resolved
// on the CPU, never auto): 0 packed RGBA8, 1 intensity (float bits), 2
// class, 3 the constant colour. Alpha 1.
vec4 attribute_color(int source, uint bits, float intensity_scale, vec4 constant_color) {
  if (source == 0) return vec4(vec3(unpackUnorm4x8(bits)), 1.0f);
  if (source == 1) return vec4(vec3(clamp(uintBitsToFloat(bits) * intensity_scale, 0.0f, 1.0f)), 1.0f);
  if (source == 2) return vec4(class_color(bits), 1.0f);
  return vec4(vec3(constant_color), 1.0f);
}

// A unit normal, or vec3(0) where the point has none worth using (packed as
// zero: degenerate neighbourhoods, non-finite input).
vec3 unit_or_zero(vec3 n) {
  float len = length(n);
  return len > 1e-3f ? n / len : vec3(0.0f);
}

// Diffuse light, two-sided (estimated normals need not face the camera);
// unlit where there is no normal. strength 0: the colour as it is.
vec3 diffuse_shaded(vec3 rgb, vec3 n, vec3 light_dir, float strength) {
  float lambert = n != vec3(0.0f) ? abs(dot(n, light_dir)) : 1.0f;
  return rgb * (1.0f - strength * (1.0f - lambert));
}
#endif
