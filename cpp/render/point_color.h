#pragma once
// shaders/point_color.glsl for the native backends: a point's colour under
// its colour source, the class palette and diffuse light, the same text the
// shaders compile.
#include "core/glsl.h"

namespace pointnpr::glsl {
namespace {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "point_color.glsl"
#pragma GCC diagnostic pop
}  // namespace
}  // namespace pointnpr::glsl
