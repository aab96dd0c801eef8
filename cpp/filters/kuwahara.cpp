// Oil paint: anisotropic Kuwahara filter (Kyprianidis, Kang and Doellner
// 2009) with the polynomial sector weights of Kyprianidis, Semmo, Kang and
// Doellner 2010 (8 sectors, no weight texture). A structure tensor on
// covered pixels, smoothed by a Gaussian, gives each pixel an orientation
// and anisotropy; the filter window is an ellipse aligned with it, split
// into 8 overlapping sectors, and the output is the variance-weighted mean
// of the sector means. Only covered pixels are read or written, so the
// background never bleeds in and the outline stays where it was.
// Optional impasto (after Semmo, Limberger, Kyprianidis and Doellner 2016):
// a paint height field, noise smeared along the local edge direction
// (bristle streaks) plus paint thickness from lightness, lit as a bump map.
#include <algorithm>
#include <cmath>

#include "filters/filter_util.h"

namespace pointnpr {
namespace {

class Kuwahara final : public Filter {
 public:
  static int tensor_radius(const ParamValues& p) { return filters::gauss_radius(p.get_float("tensor_sigma")); }
  static int window_radius(const ParamValues& p) {
    return int(std::ceil(2.0 * p.get_float("radius")));  // ellipse axes are at most 2 r
  }
  // Writes only covered pixels; reads the ellipse, and the tensor's kernel.
  static int impasto_margin(const ParamValues& p) { return p.get_float("impasto") > 0.0 ? 1 : 0; }
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    return std::max(window_radius(p), tensor_radius(p) + 1) + impasto_margin(p);
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const int rt = tensor_radius(p);
    const gl::Texture& tensor = ctx.scratch(0);
    const gl::Texture& smooth_x = ctx.scratch(1);
    const gl::Texture& smooth = ctx.scratch(2);
    const bool impasto = impasto_margin(p) > 0;
    // The impasto shading reads the filtered image and height 1 px around.
    const Rect area = ctx.rect.grown(impasto_margin(p), ctx.image_size);
    filters::structure_tensor(ctx, *ctx.input, area, rt, float(p.get_float("tensor_sigma")), tensor, smooth_x, smooth);
    const gl::Program& prog = ctx.shaders->compute("kuwahara.comp", {"PASS_FILTER"});
    prog.use();
    const double r = p.get_float("radius");
    const double zeta = std::clamp(2.0 / r, 0.05, 1.0);  // sector overlap (2010 paper)
    const double s = std::sin(M_PI / 8.0);
    glUniform1f(prog.location("u_window"), float(r));
    glUniform1f(prog.location("u_alpha"), float(p.get_float("anisotropy")));
    glUniform1f(prog.location("u_q"), float(p.get_float("sharpness")));
    glUniform1f(prog.location("u_zeta"), float(zeta));
    glUniform1f(prog.location("u_eta"), float((zeta + std::cos(M_PI / 8.0)) / (s * s)));
    const gl::Texture& filtered = impasto ? ctx.scratch(3) : *ctx.output;
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, filtered, GL_WRITE_ONLY);
    filters::bind_image(2, smooth, GL_READ_ONLY);
    dispatch_rect(prog, impasto ? area : ctx.rect);
    if (!impasto) return;
    const gl::Texture& height = smooth_x;  // free again
    const gl::Program& hp = ctx.shaders->compute("kuwahara.comp", {"PASS_HEIGHT"});
    hp.use();
    glUniform1f(hp.location("u_brush_size"), float(p.get_float("brush_size")));
    glUniform1i(hp.location("u_stroke_length"), int(std::ceil(p.get_float("stroke_length"))));
    filters::bind_image(0, filtered, GL_READ_ONLY);
    filters::bind_image(1, height, GL_WRITE_ONLY);
    filters::bind_image(2, smooth, GL_READ_ONLY);
    dispatch_rect(hp, area);
    const gl::Program& sp = ctx.shaders->compute("kuwahara.comp", {"PASS_SHADE"});
    sp.use();
    glUniform1f(sp.location("u_relief"), float(p.get_float("impasto")));
    filters::bind_image(0, filtered, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    filters::bind_image(2, height, GL_READ_ONLY);
    dispatch_rect(sp, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"kuwahara",
           "Oil Paint (Kuwahara)",
           "Anisotropic Kuwahara filter: flat, brush-like regions that follow the image structure, edges kept sharp.",
           {
               float_param("radius", 6.0, 2.0, 16.0, "px", "Radius of the filter window (brush size)"),
               float_param("sharpness", 8.0, 1.0, 16.0, "", "q: how strongly low-variance sectors win (edge sharpness)"),
               float_param("anisotropy", 1.0, 0.1, 10.0, "", "alpha: lower values stretch the window more along edges"),
               float_param("tensor_sigma", 2.0, 0.5, 8.0, "px", "Smoothing of the structure tensor (orientation field)"),
               float_param("impasto", 0.5, 0.0, 4.0, "", "Relief of the paint texture, lit as a bump map (0 = flat)"),
               float_param("brush_size", 1.5, 0.5, 8.0, "px", "Width of the bristle streaks in the paint"),
               float_param("stroke_length", 8.0, 1.0, 32.0, "px", "Length over which the streaks follow the image structure"),
           }},
    [] { return std::make_unique<Kuwahara>(); }}};

}  // namespace
}  // namespace pointnpr
