// GLSL's half of the subset kernels shared with the native backends are
// written in (cpp/core/glsl.h, the C++ half, says what the subset is).
#ifndef SHARED_KERNELS_GLSL
#define SHARED_KERNELS_GLSL
#define SETTINGS_BLOCK(name, slot) layout(std140, binding = slot) uniform name {
#define END_SETTINGS_BLOCK(instance) } instance;
// A product whose rounding the compiler must not change (GLSL's precise).
#define PRECISE precise
// mat4 * vec4, spelled so the native backends sum the columns in order as
// llvmpipe does.
vec4 mat_vec(mat4 m, vec4 v) { return m * v; }
#endif
