// Hole filling, the gap-handling pre-pass seed 000's discussion asks for:
// a background pixel enclosed by points (points within `radius` on both
// sides of at least `enclosure` of the 4 lines through it: horizontal,
// vertical, both diagonals) is painted with the coverage-normalized
// Gaussian mean of its neighbours. Holes between the points of a surface
// close whatever the surface's density; the outside of a region's border
// (points on one side only) and lone points farther apart than 2 `radius`
// do not grow. Put it first in a chain for sparse clouds.
#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class FillHoles final : public Filter {
 public:
  static double sigma(const ParamValues& p) { return 0.5 * p.get_int("radius"); }
  // Writes only enclosed holes; reads the kernel (>= radius) around.
  int footprint(const ParamValues& p) const override { return filters::gauss_radius(sigma(p)); }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const int radius = footprint(p);
    const double s = sigma(p);
    const gl::Texture& sums = ctx.scratch(0);
    for (const char* pass : {"PASS_X", "PASS_Y"}) {
      const bool x = pass[5] == 'X';
      const gl::Program& prog = ctx.shaders->compute("fill_holes.comp", {pass});
      prog.use();
      glUniform1f(prog.location("u_sigma"), float(s));
      glUniform1i(prog.location("u_radius"), radius);
      glUniform1i(prog.location("u_reach"), p.get_int("radius"));
      glUniform1i(prog.location("u_axes"), p.get_int("enclosure"));
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(1, x ? sums : *ctx.output, GL_WRITE_ONLY);
      filters::bind_image(2, sums, GL_READ_ONLY);
      dispatch_rect(prog, x ? filters::grown_rows(ctx.rect, radius, ctx.image_size) : ctx.rect);
    }
  }
};

const FilterRegistration registration{{
    Schema{"fill_holes",
           "Fill Holes",
           "Closes the gaps between the points of a surface (before other filters); lone points do not grow.",
           {
               int_param("radius", 3, 1, 16, "px", "Holes up to this radius close (gaps up to twice this wide)"),
               int_param("enclosure", 2, 1, 4, "",
                         "Of the 4 lines through a hole, how many must meet points on both sides"),
           }},
    [] { return std::make_unique<FillHoles>(); }}};

}  // namespace
}  // namespace pointnpr
