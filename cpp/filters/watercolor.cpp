// Watercolor after Bousseau, Kaplan, Thollot and Sillion 2006 ("Interactive
// watercolor rendering with temporal coherence and abstraction"):
//  - abstraction: a coverage-normalized separable bilateral filter of the
//    colours (Bousseau uses mean shift; this keeps edges at GPU speed);
//  - wobbling: the abstracted image is looked up through a smooth paper
//    noise displacement, so region borders turn irregular;
//  - edge darkening: pigment gathers where the abstracted colour changes
//    and along the border of each wet region (its coverage falls off);
//  - pigment density variation (low-frequency turbulence) and granulation
//    (pigment settling in the paper's valleys), all through Bousseau's
//    density model C' = C - (C - C^2)(d - 1);
//  - dry brush (as in the real-time watercolor of Montesdeoca et al. 2017):
//    a dry brush leaves pigment only on the paper's peaks, most along region
//    borders, so the paper colour shows through in the valleys.
// The paper is a height map image read through OpenImageIO (white = peaks,
// tiled, fixed to the screen like a real sheet), or when none is given a
// procedural one: fractal value noise hashed from pixel coordinates and
// `seed`. Three procedural papers made by scripts/make_textures.py ship
// with the add-on (pointnpr.paper_textures()). Wobble and density variation
// stay procedural: they are lower frequencies than any paper grain.
// Holes narrower than the edge width are painted over; lone points keep
// their colour (with pigment effects) and get no darkened rim.
#include <algorithm>
#include <cmath>

#include "core/image_io.h"
#include "filters/filter_util.h"
#include "render/image_textures.h"

namespace pointnpr {
namespace {

struct Sizes {
  double sigma_abstract, sigma_fill;
  int kernel, wobble;
};

Sizes sizes(const ParamValues& p) {
  Sizes s;
  s.sigma_abstract = p.get_float("abstraction");
  s.sigma_fill = 0.5 * p.get_float("edge_width");
  s.kernel = std::max(filters::gauss_radius(s.sigma_abstract), filters::gauss_radius(s.sigma_fill));
  s.wobble = int(std::ceil(p.get_float("wobble")));
  return s;
}

class Watercolor final : public Filter {
 public:
  // Borders move by up to `wobble` px; lookups reach 2 px and the kernel beyond.
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    const Sizes s = sizes(p);
    return s.wobble + 2 + s.kernel;
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const Sizes s = sizes(p);
    const Rect abstract_rect = ctx.rect.grown(s.wobble + 2, ctx.image_size);
    const gl::Texture& sums_a = ctx.scratch(0);
    const gl::Texture& sums_b = ctx.scratch(1);
    const gl::Texture& abstract = ctx.scratch(2);
    for (const char* pass : {"PASS_ABSTRACT_X", "PASS_ABSTRACT_Y"}) {
      const bool x = pass[14] == 'X';
      const gl::Program& prog = ctx.shaders->compute("watercolor.comp", {pass});
      prog.use();
      glUniform1f(prog.location("u_sigma"), float(std::max(s.sigma_abstract, 1e-3)));
      glUniform1f(prog.location("u_fill_sigma"), float(std::max(s.sigma_fill, 1e-3)));
      glUniform1i(prog.location("u_radius"), s.kernel);
      glUniform1f(prog.location("u_tolerance"), float(p.get_float("abstraction_tolerance")));
      double norm = 0.0;
      for (int i = -s.kernel; i <= s.kernel; ++i)
        norm += std::exp(-double(i * i) / (2.0 * std::max(s.sigma_fill, 1e-3) * std::max(s.sigma_fill, 1e-3)));
      glUniform1f(prog.location("u_fill_norm"), float(norm * norm));
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      if (x) {
        filters::bind_image(2, sums_a, GL_WRITE_ONLY);
        filters::bind_image(3, sums_b, GL_WRITE_ONLY);
      } else {
        filters::bind_image(4, sums_a, GL_READ_ONLY);
        filters::bind_image(5, sums_b, GL_READ_ONLY);
        filters::bind_image(1, abstract, GL_WRITE_ONLY);
      }
      dispatch_rect(prog, x ? filters::grown_rows(abstract_rect, s.kernel, ctx.image_size) : abstract_rect);
    }
    const std::string& paper_path = p.get_path("paper");
    const gl::Texture* paper = nullptr;
    if (!paper_path.empty())
      paper = &ctx.images->get(paper_path, "paper", ImageTextures::Sampling::Tiled, [](Image i) { return i; });
    const gl::Program& prog = ctx.shaders->compute("watercolor.comp", {"PASS_COMPOSE"});
    prog.use();
    glBindTextureUnit(0, paper ? paper->id() : 0);
    glUniform1i(prog.location("u_paper"), 0);
    glUniform1i(prog.location("u_paper_image"), paper ? 1 : 0);
    glUniform1f(prog.location("u_dry_brush"), float(p.get_float("dry_brush")));
    filters::set_color(prog, "u_paper_color", p.get_color("paper_color"));
    glUniform1f(prog.location("u_wobble"), float(p.get_float("wobble")));
    glUniform1f(prog.location("u_wobble_scale"), float(p.get_float("wobble_scale")));
    glUniform1f(prog.location("u_edge_darkening"), float(p.get_float("edge_darkening")));
    glUniform1f(prog.location("u_density"), float(p.get_float("pigment_density")));
    glUniform1f(prog.location("u_density_scale"), float(p.get_float("density_scale")));
    glUniform1f(prog.location("u_granulation"), float(p.get_float("granulation")));
    glUniform1f(prog.location("u_paper_scale"), float(p.get_float("paper_scale")));
    glUniform1ui(prog.location("u_seed"), uint32_t(p.get_int("seed")));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    filters::bind_image(4, abstract, GL_READ_ONLY);
    dispatch_rect(prog, ctx.rect);
    glBindTextureUnit(0, 0);
  }
};

const FilterRegistration registration{{
    Schema{"watercolor",
           "Watercolor",
           "Abstracted washes with wobbly borders, darkened edges, pigment variation and paper granulation.",
           {
               float_param("abstraction", 2.0, 0.0, 8.0, "px", "Spatial sigma of the edge-preserving blur before painting"),
               float_param("abstraction_tolerance", 0.15, 0.01, 1.0, "",
                           "Colour difference (sRGB) the abstraction blurs across; colour edges above it stay"),
               float_param("wobble", 2.0, 0.0, 8.0, "px", "How far the paper displaces region borders"),
               float_param("wobble_scale", 24.0, 4.0, 256.0, "px", "Feature size of the border wobble"),
               float_param("edge_darkening", 1.0, 0.0, 2.0, "", "Pigment gathered at colour edges and region borders"),
               float_param("edge_width", 3.0, 1.0, 12.0, "px",
                           "Width of the darkened rim; holes narrower than this are painted over"),
               float_param("pigment_density", 0.3, 0.0, 1.0, "", "Low-frequency variation of pigment density"),
               float_param("density_scale", 64.0, 4.0, 512.0, "px", "Feature size of the density variation"),
               float_param("granulation", 0.3, 0.0, 1.0, "", "Pigment settling in the paper grain"),
               float_param("dry_brush", 0.0, 0.0, 1.0, "",
                           "Dry brush: pigment only on the paper's peaks, most along region borders"),
               only_when(color_param("paper_color", {0.98, 0.97, 0.94, 1.0}, "Paper showing through a dry brush (display sRGB)"),
                         "dry_brush", {"nonzero"}),
               image_param("paper", "Paper height map (grey, white = peaks), tiled; none = procedural paper"),
               float_param("paper_scale", 3.0, 1.0, 16.0, "px", "Paper grain size: pixels per texel of the image, or the procedural cell"),
               int_param("seed", 0, 0, 65535, "", "Paper texture seed (same paper under every segment)"),
           }},
    [] { return std::make_unique<Watercolor>(); }}};

}  // namespace
}  // namespace pointnpr
