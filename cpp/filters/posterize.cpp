// Posterize: each covered pixel's colour is quantized to `levels` steps,
// per sRGB channel, or in Oklab (perceptual: lightness only, or all three
// axes). Background stays untouched; writes nothing outside coverage.
// Soft quantization by default (Winnemoller et al. 2006): hard steps turn
// the scan's small frame-to-frame changes near a band border into whole
// steps (1.4x the unfiltered flicker on the lion orbit, docs/filters.md);
// smoothness 0.6 brings that to about the unfiltered render's.
#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class Posterize final : public Filter {
 public:
  int footprint(const ParamValues&) const override { return 0; }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const gl::Program& prog = ctx.shaders->compute("posterize.comp");
    prog.use();
    glUniform1i(prog.location("u_levels"), p.get_int("levels"));
    glUniform1i(prog.location("u_space"), p.get_enum("space"));
    glUniform1f(prog.location("u_smoothness"), float(p.get_float("smoothness")));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"posterize",
           "Posterize",
           "Quantizes colours to a few levels per channel, in sRGB or in the perceptual Oklab space.",
           {
               int_param("levels", 5, 2, 64, "", "Number of levels per channel (lightness only: tones)"),
               enum_param("space", {"rgb", "lightness", "oklab"}, 1,
                          "Quantize sRGB channels, Oklab lightness only (keeps hues), or all Oklab axes"),
               float_param("smoothness", 0.6, 0.0, 1.0, "",
                           "Softens band borders against flicker in animation (0 = hard steps, exactly `levels` values)"),
           }},
    [] { return std::make_unique<Posterize>(); }}};

}  // namespace
}  // namespace pointnpr
