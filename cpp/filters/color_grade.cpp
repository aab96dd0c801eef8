// Colour grading of a segment: exposure in scene-linear light, then
// contrast, saturation and hue rotation in Oklab (perceptual, so a hue
// shift keeps lightness and saturation changes keep hue). Per pixel;
// background untouched. A look-up-table image is not supported yet.
#include <cmath>

#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class ColorGrade final : public Filter {
 public:
  int footprint(const ParamValues&) const override { return 0; }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const gl::Program& prog = ctx.shaders->compute("color_grade.comp");
    prog.use();
    const double hue = p.get_float("hue_shift") * M_PI / 180.0;
    glUniform1f(prog.location("u_gain"), float(std::exp2(p.get_float("exposure"))));
    glUniform1f(prog.location("u_contrast"), float(p.get_float("contrast")));
    glUniform1f(prog.location("u_saturation"), float(p.get_float("saturation")));
    glUniform2f(prog.location("u_hue"), float(std::cos(hue)), float(std::sin(hue)));
    glUniform1f(prog.location("u_gamma"), float(p.get_float("gamma")));
    filters::set_color(prog, "u_tint", p.get_color("tint"));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"color_grade",
           "Color Grade",
           "Exposure, contrast, saturation, hue shift, gamma and tint of the segment's colours.",
           {
               float_param("exposure", 0.0, -10.0, 10.0, "EV", "Brightness in stops, applied in scene-linear light"),
               float_param("contrast", 1.0, 0.0, 4.0, "", "Lightness contrast around middle grey (1 = unchanged)"),
               float_param("saturation", 1.0, 0.0, 4.0, "", "Chroma scale (0 = grey, 1 = unchanged)"),
               float_param("hue_shift", 0.0, -180.0, 180.0, "deg", "Rotation of hues in Oklab"),
               float_param("gamma", 1.0, 0.1, 10.0, "", "Power on scene-linear light after exposure (1 = unchanged)"),
               color_param("tint", {1.0, 1.0, 1.0, 1.0},
                           "Multiplies scene-linear colour (white = unchanged; alpha unused)"),
           }},
    [] { return std::make_unique<ColorGrade>(); }}};

}  // namespace
}  // namespace pointnpr
