// Shared by the feature_strokes mark's GL passes (cpp/marks/feature_strokes/).
#include "id_hash.glsl"
#include "shared_kernels.glsl"
#include "feature_strokes_settings.glsl"
layout(std430, binding = 7) buffer Records { Record records[]; };
