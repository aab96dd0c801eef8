// Edge enhancement from geometry, on the segment's rasterized linear depth:
//  - eye-dome lighting (Boucheny 2009, as in Potree and CloudCompare): each
//    pixel is darkened by exp(-strength * 300 * mean over 8 neighbours at
//    `edl_radius` (interpolated between the pixels along each of the 8
//    lattice directions) of max(0, log2 z - log2 z_neighbour));
//  - depth-discontinuity outlines: pixels within `outline_width` of a
//    surface nearer by more than `depth_threshold` (relative) take the edge
//    colour, so each occluding contour gets a line on its far side;
//  - crease outlines (normal discontinuities): lines `outline_width` wide
//    where the surface turns by more than `crease_angle` (normals 3 px to
//    either side compared, non-maximum suppressed to the crease itself);
//    normals come from least-squares planes fitted to the depth over 5x5
//    pixels (shaders/surface_fit.glsl), so scan noise does not make creases;
//  - silhouettes against the background around dense regions only (a
//    covered pixel counts when `density` of its (2 fill_gaps + 1)^2 box is
//    covered), so lone points get no rings; holes inside dense regions stay.
// Depth steps no larger than the scan's spacing (FilterContext::sampling)
// are its noise (a Kinect wall's quantised depth): EDL and outlines count a
// neighbour as nearer only beyond them.
// Depth is the rasterizer's: put this filter before filters that move
// pixels (warp, watercolor wobble); pixels without depth are left as they are.
#include <algorithm>
#include <cmath>

#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class EdgeEnhance final : public Filter {
 public:
  static int reach(const ParamValues& p) {
    // EDL interpolates depth up to floor(radius) + 1 pixels away.
    return std::max(int(std::floor(p.get_float("edl_radius"))) + 1, p.get_int("outline_width"));
  }
  // Creases compare normals up to w + 3 px away (shader: CREASE_STEP and
  // the non-maximum test), each fitted over 2 px around it.
  static constexpr int kCreaseReach = 3, kFitRadius = 2;
  // Silhouettes read the coverage around each pixel: the gaps between an
  // aerial tile's scan lines must not become lines.
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    return reach(p) + std::max(p.get_int("fill_gaps"), creases(p) ? kCreaseReach + kFitRadius : 0);
  }
  static bool creases(const ParamValues& p) { return p.get_float("crease_angle") > 0.0 && p.get_int("outline_width") > 0; }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const gl::Texture& normals = ctx.scratch(0);
    if (creases(p)) {
      const gl::Program& pass = ctx.shaders->compute("edge_enhance.comp", {"PASS_NORMALS"});
      pass.use();
      set_surface_uniforms(pass, ctx.surface);
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(2, *ctx.raster_depth, GL_READ_ONLY);
      filters::bind_image(3, normals, GL_WRITE_ONLY);
      dispatch_rect(pass, ctx.rect.grown(p.get_int("outline_width") + kCreaseReach, ctx.image_size));
    }
    const gl::Program& prog = ctx.shaders->compute("edge_enhance.comp");
    prog.use();
    const double crease = p.get_float("crease_angle") * M_PI / 180.0;
    glUniform1f(prog.location("u_crease_cos"), creases(p) ? float(std::cos(crease)) : 2.0f);
    filters::bind_image(3, normals, GL_READ_ONLY);
    glUniform1f(prog.location("u_edl_strength"), float(p.get_float("edl_strength")));
    glUniform1f(prog.location("u_edl_radius"), float(p.get_float("edl_radius")));
    glUniform1i(prog.location("u_outline_width"), p.get_int("outline_width"));
    glUniform1f(prog.location("u_depth_threshold"), float(p.get_float("depth_threshold")));
    glUniform1f(prog.location("u_depth_floor"), ctx.sampling.spacing);
    glUniform1i(prog.location("u_silhouette"), p.get_bool("silhouette") ? 1 : 0);
    glUniform1i(prog.location("u_fill"), p.get_int("fill_gaps"));
    glUniform1f(prog.location("u_density"), float(p.get_float("density")));
    filters::set_color(prog, "u_edge_color", p.get_color("edge_color"));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    filters::bind_image(2, *ctx.raster_depth, GL_READ_ONLY);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"edge_enhance",
           "Edge Enhancement",
           "Eye-dome lighting, depth-discontinuity and crease outlines from the segment's depth.",
           {
               float_param("edl_strength", 0.4, 0.0, 10.0, "", "Eye-dome lighting strength (0 = off; Potree uses 1)"),
               float_param("edl_radius", 1.4, 1.0, 8.0, "px", "Distance of the 8 depth neighbours"),
               int_param("outline_width", 1, 0, 8, "px", "Width of depth-discontinuity and silhouette lines (0 = none)"),
               float_param("depth_threshold", 0.05, 0.001, 1.0, "",
                           "Relative depth jump that makes a contour (0.05 = 5 % of the distance)"),
               float_param("crease_angle", 0.0, 0.0, 180.0, "deg",
                           "Outline where the surface turns by more than this (normal discontinuity; 0 = off)"),
               bool_param("silhouette", true, "Also outline dense regions against the background"),
               color_param("edge_color", {0.0, 0.0, 0.0, 1.0}, "Colour of the lines (display sRGB; alpha = opacity)"),
               int_param("fill_gaps", 3, 0, 8, "px", "Box radius for the density test of silhouettes"),
               float_param("density", 0.5, 0.05, 1.0, "",
                           "Covered fraction of the box that makes a pixel part of a surface (lone points are not)"),
           }},
    [] { return std::make_unique<EdgeEnhance>(); }}};

}  // namespace
}  // namespace pointnpr
