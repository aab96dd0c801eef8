// The stipples mark's settings, declared once for both backends in
// shaders/stipples_settings.glsl (the subset of core/glsl.h): the frame's
// (one uniform block on GL) and a window's (another).
#pragma once

#include "core/glsl.h"

namespace pointnpr::stipples {
using namespace glsl;
#include "stipples_settings.glsl"
}  // namespace pointnpr::stipples
