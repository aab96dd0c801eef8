// The gaussians mark: a 3D Gaussian splat capture (3DGS PLY, SPZ) drawn
// faithfully, as the 3DGS reference rasterizer draws it: every splat's
// anisotropic Gaussian projected to the screen (EWA, 0.3 px low-pass),
// coloured by its spherical harmonics seen from the camera, composited front
// to back in display sRGB, the colour space captures are trained in (the
// compositor then turns it to scene-linear like every scan colour). Depth
// and coverage let it composite with other segments and meshes. Floaters
// (too transparent, too large, too isolated splats) can be dropped by
// keyframeable thresholds. Native backend (TBB over 16 px tiles):
// marks/gaussians/native.cpp; the shared maths: shaders/gaussians_kernels.glsl.
#include "marks/gaussians/gaussians.h"

#include <string>

#include "render/backend.h"

namespace pointnpr::gaussians {
namespace {

class Gaussians final : public Mark {
 public:
  // Positions only from the GPU cache: the splats' own parameters are read
  // from the cloud on the host.
  AttributeSet attributes(const ParamValues& p) const override {
    AttributeSet set;
    if (queue_enabled(p)) set.insert({AttributeKind::QueueOrder});
    return set;
  }

  MarkExtent extent(const ParamValues& p) const override { return {0.0, float(p.get_float("max_radius")) + 1.0f}; }

  // A pixel's splats are those whose box (within max_radius of their
  // centre, in frame pixels less the tile's origin) holds it, in one total
  // order: every tile draws the frame's bytes.
  bool draws_tiles(const ParamValues&) const override { return true; }

  void draw(const MarkContext& ctx, const ParamValues& p) const override {
    DrawSettings s;
    s.sh_degree = p.get_int("sh_degree");
    s.max_radius = float(p.get_float("max_radius"));
    s.depth_alpha = float(p.get_float("depth_alpha"));
    s.min_coverage = float(p.get_float("min_coverage"));
    s.min_opacity = float(p.get_float("min_opacity"));
    s.max_scale = float(p.get_float("max_scale"));
    s.isolation = float(p.get_float("isolation"));
    // The resolution queue (render/mark.h), or the frame's point budget:
    // a prefix of each chunk's seeded order, as the other marks draw.
    if (draws_queue(ctx, p))
      for (const VisibleChunk& v : ctx.chunks) s.queue_counts.push_back(queue_count(v, p));
    s.gl = chosen_backend(p) == Backend::Gl;
    const DrawCounts counts = draw_native(ctx, s);
    if (counts.plain_points > 0 && ctx.warnings)
      ctx.warnings->push_back("gaussians: " + std::to_string(counts.plain_points) +
                              " points have no Gaussian splat parameters (a plain point cloud) and are not drawn; "
                              "give them another mark");
  }
};

const MarkRegistration registration{{
    Schema{"gaussians",
           "Gaussians",
           "Draws a 3D Gaussian splat capture (3DGS PLY, SPZ) as the 3DGS reference rasterizer does: anisotropic "
           "Gaussians, view-dependent SH colour, front-to-back alpha in display sRGB; plain points are not drawn.",
           {
               // Its GL pass was "compute" and native came first: files keep
               // their indices into that list.
               items_changed(rasterizer_param("gl: the 3DGS per-pixel compositing as a GL compute pass (projection, "
                                              "SH and sort on the CPU's threads); native: the 3DGS forward pass on "
                                              "the CPU's threads (TBB over 16 px tiles)"),
                             {"native", "compute", "auto"}, {{"compute", "gl"}}),
               int_param("sh_degree", 3, 0, 3, "",
                         "Spherical-harmonic bands of the view-dependent colour (at most the capture's own): "
                         "0 gives every splat one colour from every side"),
               float_param("min_opacity", 0.0, 0.0, 1.0, "",
                           "Floaters: splats less opaque than this are dropped (0: none)"),
               float_param("max_scale", 0.0, 0.0, 10000.0, "m",
                           "Floaters: splats whose largest axis (one standard deviation) exceeds this are dropped "
                           "(0: none)"),
               float_param("isolation", 0.0, 0.0, 1000.0, "",
                           "Floaters: splats whose mean distance to their 8 nearest neighbours exceeds this many "
                           "times the capture's median are dropped (0: none)"),
               float_param("max_radius", 512.0, 8.0, 4096.0, "px",
                           "Largest splat on screen (3 sigma), and how far beyond the segment's points it draws"),
               float_param("depth_alpha", 0.5, 0.01, 1.0, "",
                           "A pixel's depth (for compositing) is that of the splat at which its opacity first "
                           "reaches this, else of the splat that gave it most"),
               float_param("min_coverage", 0.0, 0.0, 1.0, "",
                           "Pixels less opaque than this are left empty: a capture's faint haze, which filters "
                           "that see any coverage as surface (cartoon, watercolor) would paint over (0: faithful)"),
               density_mode_param(),
               queue_level_param(0.5),
           }},
    [] { return std::make_unique<Gaussians>(); }}};

}  // namespace
}  // namespace pointnpr::gaussians
