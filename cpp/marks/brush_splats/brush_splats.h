#pragma once
// The brush_splats mark's two paths: its GL passes (brush_splats.cpp, which
// declares the schema) and the same rules on the CPU's threads (native.cpp
// and the Highway kernels it calls, native_kernels.cpp), which `rasterizer`
// `auto` takes on software GL devices (llvmpipe) for blur and none
// blending; the A-buffer stays on GL (its fallback over the budget, blur,
// is native there too).
#include "render/mark.h"
#include "render/surface_slope.h"

namespace pointnpr {

constexpr float kBrushCut = 1.0f / 255.0f;  // alpha below this is no coverage
// A brush is the pixel's surface (the depth pass) only where it covers at
// least half of it: a brush's faint rim in front of another surface blends
// over that surface instead of hiding it (the white cracks around a
// splat's border, where the surface behind was cut away and the rim alone
// left the pixel mostly uncovered).
constexpr float kSurfaceCut = 0.5f;

// The rims of brushes in front of another surface (shaders/brush_rims.glsl,
// after the resolve on both paths): a pixel's footprint at view depth d,
// footprint0 + d footprint1, to tell two surfaces apart by more than one
// turned as steeply as kSteepestSurfaceSlope from the view changes over a
// pixel; and the longest march, max_radius (no brush reaches farther on
// screen, so no rim is wider).
struct RimReach {
  float footprint0 = 0.0f, footprint1 = 0.0f;
  int reach = 0;
};
RimReach rim_reach(const MarkContext& ctx, const ParamValues& p);
// The native passes' rims (native_rims.cpp): `color` (straight RGBA),
// `depth` and the surfaces' blend offsets over a clip of `size`, rows
// within `row_span` (x first and last), `scratch` 4 floats a pixel.
void fill_rims_native(const RimReach& rim, float* color, const float* depth, const float* offset, glm::ivec2 size,
                      const std::vector<glm::ivec2>& row_span, float* scratch);

// The least a splat's depth tolerance reaches toward the camera, in the
// cloud's units: three standard deviations of the scan's own depth noise
// (Analysis::plane_deviation over normal_neighbors), so the row-to-row
// steps of a depth sensor or the noise of a range scan never cut the
// brushes behind the nearest one away (the cracks along a Kinect frame's
// rows). The depth_tolerance radii apply where they reach farther.
float brush_noise_offset(const PointCloud& cloud, const ParamValues& p);

// |q| beyond which one of the brush's Gaussians adds less than a 16th of
// the cut to the alpha (skipped: it counts as 0 on both paths).
double brush_reach(const ParamValues& p);

// How far a brush's visible part (alpha >= kBrushCut) reaches from its
// point, in splat radii, as the terms of sqrt((along stretch)^2 + across2):
// a brush whose Gaussians sit near its square's corners reaches the corner
// (along 1, across2 1), one round Gaussian in the middle about its
// inscribed circle (1, 0). max_radius bounds that reach on screen, so an
// isolated point's brush stays near it whatever its shape.
struct BrushSupport {
  float along = 1.0f, across2 = 1.0f;
};
BrushSupport brush_support(const ParamValues& p);

// Depth pass, blending (weighted average, transmittance) and the blur of
// brush_splats_tiled.vert/.frag, brush_resolve.comp and brush_blur.comp on
// the CPU's threads, uploaded into ctx.targets.color and .depth over
// ctx.clip. Every fragment is computed from its frame pixel and flat
// per-splat values and blended in point order (screen bins), so a tile is
// the frame's bytes in any process and with any thread count. Against the
// GL passes it differs in the last bits of the brush (exp(-q^lambda / 2)
// fitted by polynomial pieces) and on the splats' edges (the quad's
// coverage by uv in [0, 1] instead of the GL's fixed-point edges).
void draw_brush_splats_native(const MarkContext& ctx, const ParamValues& p);



}  // namespace pointnpr
