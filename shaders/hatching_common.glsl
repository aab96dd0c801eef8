// Shared by the hatching mark's GL passes (cpp/marks/hatching/).
#include "id_hash.glsl"
#include "shared_kernels.glsl"
#include "hatching_settings.glsl"
layout(std430, binding = 7) buffer Strokes { Stroke strokes[]; };
