// GLSL's half of the subset kernels shared with the native backends are
// written in (cpp/core/glsl.h, the C++ half, says what the subset is).
#ifndef SHARED_KERNELS_GLSL
#define SHARED_KERNELS_GLSL
#define SETTINGS_BLOCK(name, slot) layout(std140, binding = slot) uniform name {
#define END_SETTINGS_BLOCK(instance) } instance;
#endif
