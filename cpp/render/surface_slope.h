#pragma once
// The steepest a scanned surface is taken to turn from the view, as the
// tangent of the angle (70 degrees): two pixels' depths whose difference is
// within it over their distance (in the pixels' footprint) may be one
// surface. The filters' gap fill and the brush's rims tell surfaces apart
// by it (shaders/gap_fill.comp, brush_rims.glsl: u_grazing).
namespace pointnpr {

constexpr float kSteepestSurfaceSlope = 2.75f;

}  // namespace pointnpr
