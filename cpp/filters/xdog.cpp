// XDoG edges (Winnemoeller, Kyprianidis and Olsen 2012): the extended
// difference of Gaussians (1+p) G_sigma - p G_{1.6 sigma} on perceptual
// lightness, soft-thresholded at epsilon with steepness phi, drawn in an
// edge colour over the image (or alone), plus the segment's silhouette.
//
// Gaussians are taken over covered pixels only (normalized convolution), so
// background and holes between points never make edges; the silhouette is
// drawn only around "solid" regions (covered with enough covered
// neighbours, or holes surrounded by points), so lone points get no rings.
#include <algorithm>
#include <cmath>
#include <string>

#include "filters/filter_util.h"

namespace pointnpr {
namespace {

constexpr double kSurround = 1.6;  // k: sigma of the surround / sigma of the centre

struct Radii {
  double sigma, fill_sigma;
  int outline, kernel;
};

Radii radii(const ParamValues& p) {
  Radii r;
  r.sigma = std::max(0.5, 0.5 * p.get_float("thickness"));
  r.fill_sigma = 0.5 * p.get_int("fill_gaps");
  r.outline = p.get_bool("outline") ? int(std::ceil(p.get_float("thickness"))) : 0;
  r.kernel = std::max(filters::gauss_radius(kSurround * r.sigma), filters::gauss_radius(r.fill_sigma));
  return r;
}

class XDoG final : public Filter {
 public:
  // Draws the outline up to `thickness` px outside; reads the kernel beyond.
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    const Radii r = radii(p);
    return r.outline + r.kernel;
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const Radii r = radii(p);
    const Rect sums_rect = ctx.rect.grown(r.outline, ctx.image_size);
    const gl::Texture& a0 = ctx.scratch(0);
    const gl::Texture& b0 = ctx.scratch(1);
    const gl::Texture& a1 = ctx.scratch(2);
    const gl::Texture& b1 = ctx.scratch(3);
    for (const char* pass : {"PASS_BLUR_X", "PASS_BLUR_Y"}) {
      const bool x = std::string(pass) == "PASS_BLUR_X";
      const gl::Program& prog = ctx.shaders->compute("xdog.comp", {pass});
      prog.use();
      glUniform1f(prog.location("u_sigma"), float(r.sigma));
      glUniform1f(prog.location("u_fill_sigma"), float(r.fill_sigma));
      glUniform1i(prog.location("u_radius"), r.kernel);
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(2, x ? a0 : a1, GL_WRITE_ONLY);
      filters::bind_image(3, x ? b0 : b1, GL_WRITE_ONLY);
      filters::bind_image(4, a0, GL_READ_ONLY);
      filters::bind_image(5, b0, GL_READ_ONLY);
      dispatch_rect(prog, x ? filters::grown_rows(sums_rect, r.kernel, ctx.image_size) : sums_rect);
    }
    double norm = 0.0;  // 1D weight of the fill kernel; the 2D weight is its square
    for (int i = -r.kernel; i <= r.kernel; ++i)
      norm += r.fill_sigma > 0.0 ? std::exp(-double(i * i) / (2.0 * r.fill_sigma * r.fill_sigma)) : 0.0;
    const gl::Program& prog = ctx.shaders->compute("xdog.comp", {"PASS_COMPOSE"});
    prog.use();
    glUniform1f(prog.location("u_p"), float(p.get_float("sharpen")));
    glUniform1f(prog.location("u_epsilon"), float(p.get_float("threshold")));
    glUniform1f(prog.location("u_phi"), float(p.get_float("softness") > 0.0 ? 1.0 / p.get_float("softness") : 1e6));
    glUniform1f(prog.location("u_thickness"), float(p.get_float("thickness")));
    glUniform1i(prog.location("u_outline"), r.outline);
    glUniform1i(prog.location("u_lines_only"), p.get_enum("mode"));
    glUniform1f(prog.location("u_fill_norm"), float(norm * norm));
    filters::set_color(prog, "u_edge_color", p.get_color("edge_color"));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    filters::bind_image(4, a1, GL_READ_ONLY);
    filters::bind_image(5, b1, GL_READ_ONLY);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"xdog",
           "XDoG Edges",
           "Ink lines from the extended difference of Gaussians, in any colour, plus the silhouette outline.",
           {
               color_param("edge_color", {0.0, 0.0, 0.0, 1.0}, "Colour of lines and outline (display sRGB; alpha = opacity)"),
               float_param("thickness", 2.0, 1.0, 8.0, "px", "Line thickness: DoG scale (sigma = thickness / 2) and outline width"),
               float_param("sharpen", 20.0, 0.0, 200.0, "", "p: weight of the DoG added to the blurred image; more = more lines"),
               float_param("threshold", 0.0, -1.0, 1.0, "", "epsilon: lightness below which the XDoG response turns to ink"),
               float_param("softness", 0.05, 0.0, 1.0, "", "1/phi: width of the soft threshold (0 = hard)"),
               enum_param("mode", {"overlay", "lines"}, 0, "Draw lines over the image, or keep only the lines"),
               bool_param("outline", true, "Draw the silhouette of the segment's dense regions"),
               int_param("fill_gaps", 4, 0, 8, "px",
                         "Holes up to this radius count as surface; points sparser than this get no outline"),
           }},
    [] { return std::make_unique<XDoG>(); }}};

}  // namespace
}  // namespace pointnpr
