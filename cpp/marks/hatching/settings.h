// The hatching mark's settings and records, declared once for both
// backends in shaders/hatching_settings.glsl (the subset of core/glsl.h):
// the select pass's settings, the strokes it hands on, the stroke pass's
// settings and a line of a stroke. Each settings struct is uploaded as one
// uniform block (gl::check_uniform_block compares the layouts).
#pragma once

#include "core/glsl.h"
#include "core/hash.h"

namespace pointnpr::hatching {
using namespace glsl;
#include "hatching_settings.glsl"
static_assert(sizeof(Stroke) == 64, "std430 layout of Stroke");
}  // namespace pointnpr::hatching
