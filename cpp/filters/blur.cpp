// Gaussian blur over covered pixels only (normalized convolution: weights
// are multiplied by coverage and renormalized), separable in two passes, so
// background never bleeds into the segment and the segment's outline stays
// where it is. Background pixels stay untouched.
#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class Blur final : public Filter {
 public:
  // Writes only covered pixels; reads up to the kernel radius around them.
  int footprint(const ParamValues& p) const override { return filters::gauss_radius(p.get_float("sigma")); }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const int radius = footprint(p);
    const float sigma = float(p.get_float("sigma"));
    const gl::Texture& sums = ctx.scratch(0);
    for (const char* pass : {"PASS_X", "PASS_Y"}) {
      const bool x = pass[5] == 'X';
      const gl::Program& prog = ctx.shaders->compute("blur.comp", {pass});
      prog.use();
      glUniform1f(prog.location("u_sigma"), sigma);
      glUniform1i(prog.location("u_radius"), radius);
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(1, x ? sums : *ctx.output, GL_WRITE_ONLY);
      filters::bind_image(2, sums, GL_READ_ONLY);
      dispatch_rect(prog, x ? filters::grown_rows(ctx.rect, radius, ctx.image_size) : ctx.rect);
    }
  }
};

const FilterRegistration registration{{
    Schema{"blur",
           "Gaussian Blur",
           "Blurs the segment's colours without bleeding background in (coverage-normalized).",
           {
               float_param("sigma", 2.0, 0.3, 32.0, "px", "Standard deviation of the Gaussian"),
           }},
    [] { return std::make_unique<Blur>(); }}};

}  // namespace
}  // namespace pointnpr
