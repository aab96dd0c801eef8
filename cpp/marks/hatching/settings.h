// The hatching mark's settings and strokes, declared once for both
// backends in shaders/ (the subset of core/glsl.h): hatching_settings.glsl
// (uploaded as one uniform block), hatching_stroke.glsl (a point's strokes).
#pragma once

#include "core/glsl.h"

namespace pointnpr::hatching {
using namespace glsl;
#include "hatching_settings.glsl"
#include "hatching_stroke.glsl"
static_assert(sizeof(Stroke) == 64, "std430 layout of hatching_stroke.glsl");
}  // namespace pointnpr::hatching
