// Pencil hatching in image space (seed 000's pencil filter, on the GPU):
// tone (1 - Oklab lightness, averaged over covered pixels in a small box)
// is mapped to up to four layers of procedural pencil strokes at different
// angles, each layer fading in over its own tone interval (tonal art map
// style, Praun et al. 2001, generated instead of stored). Strokes are
// broken into dashes of random length and offset, wobble slightly and carry
// paper grain; everything is hashed from stroke indices and `seed`, so the
// result is deterministic. Background stays untouched.
//
// Where strokes live (`space`): on the surface (default) they are the
// intersections of the surface with families of parallel planes in the
// segment's object space, spaced in powers of two that blend with the view
// (Benard, Bousseau and Thollot 2009, dynamic solid textures): they stick
// to the surface when the camera moves, at a roughly constant density on
// screen. The surface point comes from the rasterizer's depth, smoothed by
// a least-squares plane over the neighbourhood (scan depth is noisy). On
// the screen (or where a pixel has no depth, e.g. filled holes) strokes are
// fixed to the image and surfaces slide under them.
#include <algorithm>
#include <cmath>

#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class Hatching final : public Filter {
 public:
  static constexpr int kFitRadius = 2;  // depth plane fit: 5x5 pixels at least
  int footprint(const ParamValues& p) const override { return std::max(p.get_int("tone_smoothing"), kFitRadius); }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const gl::Program& prog = ctx.shaders->compute("hatching.comp");
    prog.use();
    glUniform1i(prog.location("u_layers"), p.get_int("layers"));
    glUniform1f(prog.location("u_angle"), float(p.get_float("angle") * M_PI / 180.0));
    glUniform1f(prog.location("u_spacing"), float(p.get_float("spacing")));
    glUniform1f(prog.location("u_line_width"), float(p.get_float("line_width")));
    glUniform1f(prog.location("u_stroke_length"), float(p.get_float("stroke_length")));
    glUniform1f(prog.location("u_grain"), float(p.get_float("grain")));
    glUniform1f(prog.location("u_color_mix"), float(p.get_float("color_mix")));
    glUniform1i(prog.location("u_smooth"), p.get_int("tone_smoothing"));
    glUniform1ui(prog.location("u_seed"), uint32_t(p.get_int("seed")));
    glUniform1i(prog.location("u_surface"), p.get_enum_name("space") == "surface" ? 1 : 0);
    glUniform1i(prog.location("u_fit_radius"), kFitRadius);
    set_surface_uniforms(prog, ctx.surface);
    glBindImageTexture(2, ctx.raster_depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    filters::set_color(prog, "u_pencil", p.get_color("pencil_color"));
    filters::set_color(prog, "u_paper", p.get_color("paper_color"));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    // Was "hatching", the hatching mark's id too: styles and files naming
    // the filter so still find it (Schema::former_ids).
    Schema{"pencil_hatching",
           "Pencil Hatching",
           "Pencil strokes whose density follows the tone: more, crossing layers where the image is darker.",
           {
               enum_param("space", {"surface", "screen"}, 0,
                          "surface: strokes stick to the scan as the camera moves; screen: fixed to the image"),
               int_param("layers", 3, 1, 4, "", "Number of hatching directions (cross-hatching in dark tones)"),
               float_param("angle", 45.0, -180.0, 180.0, "deg", "Direction of the first layer of strokes"),
               float_param("spacing", 6.0, 2.0, 32.0, "px", "Distance between parallel strokes"),
               float_param("line_width", 1.2, 0.5, 4.0, "px", "Width of a stroke at mid tone (up to twice that in the darkest tone)"),
               float_param("stroke_length", 40.0, 4.0, 512.0, "px", "Typical length of one stroke"),
               color_param("pencil_color", {0.12, 0.12, 0.14, 1.0}, "Colour of the strokes (display sRGB; alpha = opacity)"),
               color_param("paper_color", {0.97, 0.96, 0.92, 1.0}, "Colour between strokes (display sRGB)"),
               float_param("color_mix", 0.0, 0.0, 1.0, "", "How much of the segment's own colour tints the paper"),
               float_param("grain", 0.5, 0.0, 1.0, "", "Paper grain breaking up the strokes"),
               int_param("tone_smoothing", 2, 0, 6, "px", "Box radius over which tone is averaged (hides scan noise)"),
               int_param("seed", 0, 0, 65535, "", "Stroke pattern seed"),
           },
           {"hatching"}},
    [] { return std::make_unique<Hatching>(); }}};

}  // namespace
}  // namespace pointnpr
