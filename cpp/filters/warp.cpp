// Warp: a travelling transverse wave that displaces the segment's image,
// its phase driven by scene time so it animates over the timeline
// (Wegen et al. 2024, Fig. 11).
#include <cmath>

#include "render/filter.h"

namespace pointnpr {
namespace {

class Warp final : public Filter {
 public:
  int footprint(const ParamValues& p) const override { return int(std::ceil(p.get_float("amplitude"))) + 1; }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const gl::Program& prog = ctx.shaders->compute("warp.comp");
    prog.use();
    const double angle = p.get_float("direction") * M_PI / 180.0;
    // Phase in cycles, reduced in double so long animations keep precision.
    const double cycles = p.get_float("speed") * ctx.time + p.get_float("phase") / 360.0;
    glUniform1f(prog.location("u_amplitude"), float(p.get_float("amplitude")));
    glUniform1f(prog.location("u_wavelength"), float(p.get_float("wavelength")));
    glUniform2f(prog.location("u_direction"), float(std::cos(angle)), float(std::sin(angle)));
    glUniform1f(prog.location("u_phase"), float(2.0 * M_PI * (cycles - std::floor(cycles))));
    glBindImageTexture(0, ctx.input->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, ctx.output->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"warp",
           "Warp",
           "Displaces the image by a travelling wave across the segment; animate it with scene time or keyframes.",
           {
               float_param("amplitude", 6.0, 0.0, 64.0, "px", "Largest displacement of a pixel"),
               float_param("wavelength", 120.0, 4.0, 4096.0, "px", "Distance between wave crests"),
               float_param("speed", 0.5, -10.0, 10.0, "Hz", "Wave cycles per second of scene time"),
               float_param("direction", 0.0, -360.0, 360.0, "deg", "Direction the wave travels (0 = +x)"),
               float_param("phase", 0.0, -360.0, 360.0, "deg", "Phase offset, for keyframing the wave by hand"),
           }},
    [] { return std::make_unique<Warp>(); }}};

}  // namespace
}  // namespace pointnpr
