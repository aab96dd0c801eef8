// Cartoon: soft luminance quantization and difference-of-Gaussians edges
// (after Winnemoeller et al. 2006), plus silhouette outlines drawn outside
// the segment, which is what depth inpainting exists for. Gaps between
// sparse points narrower than `fill_gaps` are filled first, and only dense
// regions get outlines, so lone points do not sprout rings.
#include <algorithm>
#include <cmath>

#include "render/filter.h"

namespace pointnpr {
namespace {

constexpr float kSurroundRatio = 1.6f;  // sigma_r / sigma_e (Marr-Hildreth)

class Cartoon final : public Filter {
 public:
  static int kernel_radius(const ParamValues& p) {
    return int(std::ceil(2.0 * kSurroundRatio * p.get_float("edge_sigma")));
  }
  int footprint(const ParamValues& p) const override {
    return std::max(p.get_int("outline_width"), p.get_int("fill_gaps")) + kernel_radius(p);
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const gl::Texture& smooth = ctx.scratch(0);
    const gl::Texture& edges = ctx.scratch(1);
    const int radius = std::max(kernel_radius(p), p.get_int("fill_gaps"));
    // Pass 1 also runs on the ring the outlines read.
    const Rect smooth_rect = ctx.rect.grown(p.get_int("outline_width"), ctx.image_size);
    {
      const gl::Program& prog = ctx.shaders->compute("cartoon.comp", {"PASS_SMOOTH"});
      prog.use();
      glUniform1f(prog.location("u_sigma"), float(p.get_float("edge_sigma")));
      glUniform1i(prog.location("u_radius"), radius);
      glUniform1i(prog.location("u_fill_gaps"), p.get_int("fill_gaps"));
      glBindImageTexture(0, ctx.input->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      glBindImageTexture(2, smooth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(3, edges.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      dispatch_rect(prog, smooth_rect);
    }
    const gl::Program& prog = ctx.shaders->compute("cartoon.comp", {"PASS_COMPOSE"});
    prog.use();
    const glm::vec4 edge = p.get_color("edge_color");
    glUniform1i(prog.location("u_levels"), p.get_int("levels"));
    glUniform1f(prog.location("u_sharpness"), float(p.get_float("quantize_sharpness")));
    glUniform1f(prog.location("u_edge_sensitivity"), float(p.get_float("edge_sensitivity")));
    glUniform1f(prog.location("u_edge_strength"), float(p.get_float("edge_strength")));
    glUniform1i(prog.location("u_outline_width"), p.get_int("outline_width"));
    glUniform1i(prog.location("u_fill_gaps"), p.get_int("fill_gaps"));
    glUniform4f(prog.location("u_edge_color"), edge.r, edge.g, edge.b, edge.a);
    glBindImageTexture(0, ctx.input->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, ctx.output->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(2, smooth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(3, edges.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"cartoon",
           "Cartoon",
           "Flat color bands, soft DoG edges and silhouette outlines.",
           {
               int_param("levels", 5, 2, 32, "", "Number of luminance bands"),
               float_param("quantize_sharpness", 4.0, 0.0, 50.0, "", "How hard band borders are (0 = smooth)"),
               float_param("edge_sigma", 1.0, 0.5, 4.0, "px", "Scale of the DoG edge detector"),
               float_param("edge_sensitivity", 20.0, 0.5, 200.0, "", "Steepness of the soft edge threshold"),
               float_param("edge_strength", 1.0, 0.0, 1.0, "", "Opacity of interior DoG edges"),
               int_param("outline_width", 2, 0, 16, "px", "Width of the silhouette outline drawn around the segment"),
               color_param("edge_color", {0.0, 0.0, 0.0, 1.0}, "Color of edges and outlines (display sRGB)"),
               int_param("fill_gaps", 3, 0, 8, "px", "Holes between points up to this radius are filled"),
           }},
    [] { return std::make_unique<Cartoon>(); }}};

}  // namespace
}  // namespace pointnpr
