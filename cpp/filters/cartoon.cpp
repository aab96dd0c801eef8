// Cartoon: soft luminance quantization and difference-of-Gaussians edges
// (after Winnemoeller et al. 2006) on an image first smoothed by an iterated
// separable bilateral filter in CIELAB (over covered pixels only; the
// separable approximation of Pham and van Vliet 2005), plus silhouette
// outlines drawn outside
// the segment, which is what depth inpainting exists for. Gaps between
// sparse points narrower than `fill_gaps` are filled first, and only dense
// regions get outlines, so lone points do not sprout rings.
#include <algorithm>
#include <cmath>
#include <string>

#include "render/filter.h"

namespace pointnpr {
namespace {

constexpr float kSurroundRatio = 1.6f;  // sigma_r / sigma_e (Marr-Hildreth)

class Cartoon final : public Filter {
 public:
  static int kernel_radius(const ParamValues& p) {
    return int(std::ceil(2.0 * kSurroundRatio * p.get_float("edge_sigma")));
  }
  static int bilateral_radius(const ParamValues& p) {
    return int(std::ceil(2.0 * p.get_float("smoothing_sigma")));
  }
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    // Writes up to outline_width outside; reads its kernel beyond that, and
    // each bilateral iteration reads its own radius further.
    return p.get_int("outline_width") + std::max(p.get_int("fill_gaps"), kernel_radius(p)) +
           p.get_int("smoothing") * bilateral_radius(p);
  }

  // Iterated separable bilateral filter; returns the image to go on with
  // (display sRGB, valid on `valid`).
  const gl::Texture* smooth(const FilterContext& ctx, const ParamValues& p, const Rect& valid) const {
    const int iterations = p.get_int("smoothing");
    if (iterations == 0) return ctx.input;
    const int rb = bilateral_radius(p);
    const gl::Texture* images[2] = {&ctx.scratch(4), &ctx.scratch(5)};
    const gl::Program& prog = ctx.shaders->compute("cartoon.comp", {"PASS_BILATERAL"});
    prog.use();
    glUniform1f(prog.location("u_space_sigma"), float(p.get_float("smoothing_sigma")));
    glUniform1f(prog.location("u_range_sigma"), float(p.get_float("smoothing_range")));
    // Convert once to CIELAB where the first iteration reads.
    glUniform2i(prog.location("u_axis"), 0, 0);
    glUniform1i(prog.location("u_in_srgb"), 1);
    glUniform1i(prog.location("u_out_srgb"), 0);
    glUniform1i(prog.location("u_bilateral_radius"), 0);
    glBindImageTexture(0, ctx.input->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, images[1]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    dispatch_rect(prog, valid.grown(rb * iterations, ctx.image_size));
    glUniform1i(prog.location("u_in_srgb"), 0);
    glUniform1i(prog.location("u_bilateral_radius"), rb);
    for (int it = 0; it < iterations; ++it) {
      // Iteration `it` must be valid where the later ones read.
      const Rect r = valid.grown(rb * (iterations - 1 - it), ctx.image_size);
      for (int axis = 0; axis < 2; ++axis) {
        glUniform2i(prog.location("u_axis"), axis == 0 ? 1 : 0, axis == 0 ? 0 : 1);
        glUniform1i(prog.location("u_out_srgb"), it == iterations - 1 && axis == 1 ? 1 : 0);
        glBindImageTexture(0, images[1 - axis]->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(1, images[axis]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        const Rect rows{{r.min.x, std::max(r.min.y - rb, 0)}, {r.max.x, std::min(r.max.y + rb, ctx.image_size.y)}};
        dispatch_rect(prog, axis == 0 ? rows : r);
      }
    }
    return images[1];
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const int fill = p.get_int("fill_gaps");
    const float sigma = float(p.get_float("edge_sigma"));
    const float fill_sigma = float(fill) * 0.5f;
    const int radius = std::max(kernel_radius(p), fill);
    // The blurred sums are also read on the ring the outlines look into.
    const Rect sums_rect = ctx.rect.grown(p.get_int("outline_width"), ctx.image_size);
    const gl::Texture* input = smooth(ctx, p, sums_rect.grown(radius, ctx.image_size));
    const gl::Texture* sums[4] = {&ctx.scratch(0), &ctx.scratch(1), &ctx.scratch(2), &ctx.scratch(3)};
    for (const char* pass : {"PASS_BLUR_X", "PASS_BLUR_Y"}) {
      const bool x = std::string(pass) == "PASS_BLUR_X";
      const gl::Program& prog = ctx.shaders->compute("cartoon.comp", {pass});
      prog.use();
      glUniform1f(prog.location("u_sigma"), sigma);
      glUniform1f(prog.location("u_fill_sigma"), fill_sigma);
      glUniform1i(prog.location("u_radius"), radius);
      if (x) {
        glBindImageTexture(0, input->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      } else {
        glBindImageTexture(4, sums[0]->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(5, sums[1]->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      }
      glBindImageTexture(2, sums[x ? 0 : 2]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(3, sums[x ? 1 : 3]->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      // The vertical pass reads rows the horizontal pass must have written.
      const Rect rows{{sums_rect.min.x, std::max(sums_rect.min.y - radius, 0)},
                      {sums_rect.max.x, std::min(sums_rect.max.y + radius, ctx.image_size.y)}};
      dispatch_rect(prog, x ? rows : sums_rect);
    }
    // Total weight of the 2D fill kernel, to turn sums into a coverage fraction.
    double norm = 0.0;
    for (int i = -radius; i <= radius; ++i) norm += fill > 0 ? std::exp(-double(i * i) / (2.0 * fill_sigma * fill_sigma)) : 0.0;
    const gl::Program& prog = ctx.shaders->compute("cartoon.comp", {"PASS_COMPOSE"});
    prog.use();
    const glm::vec4 edge = p.get_color("edge_color");
    glUniform1i(prog.location("u_levels"), p.get_int("levels"));
    glUniform1f(prog.location("u_sharpness"), float(p.get_float("quantize_sharpness")));
    glUniform1f(prog.location("u_edge_sensitivity"), float(p.get_float("edge_sensitivity")));
    glUniform1f(prog.location("u_edge_strength"), float(p.get_float("edge_strength")));
    glUniform1i(prog.location("u_outline_width"), p.get_int("outline_width"));
    glUniform1f(prog.location("u_fill_norm"), float(norm * norm));
    glUniform4f(prog.location("u_edge_color"), edge.r, edge.g, edge.b, edge.a);
    glBindImageTexture(0, input->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, ctx.output->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(4, sums[2]->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(5, sums[3]->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    dispatch_rect(prog, ctx.rect);
  }
};

const FilterRegistration registration{{
    Schema{"cartoon",
           "Cartoon",
           "Flat color bands, soft DoG edges and silhouette outlines.",
           {
               int_param("levels", 5, 2, 32, "", "Number of luminance bands"),
               float_param("quantize_sharpness", 4.0, 0.0, 50.0, "",
                           "How hard band borders are: 0 = no bands (smooth), larger = flatter bands, sharper steps"),
               float_param("edge_sigma", 1.0, 0.5, 4.0, "px", "Scale of the DoG edge detector"),
               float_param("edge_sensitivity", 20.0, 0.5, 200.0, "", "Steepness of the soft edge threshold"),
               float_param("edge_strength", 1.0, 0.0, 1.0, "", "Opacity of interior DoG edges"),
               int_param("outline_width", 2, 0, 16, "px", "Width of the silhouette outline drawn around the segment"),
               color_param("edge_color", {0.0, 0.0, 0.0, 1.0}, "Color of edges and outlines (display sRGB)"),
               int_param("fill_gaps", 3, 0, 8, "px", "Holes between points up to this radius are filled"),
               int_param("smoothing", 1, 0, 4, "", "Iterations of the edge-preserving (bilateral) smoothing before banding"),
               float_param("smoothing_sigma", 2.0, 0.5, 6.0, "px", "Spatial extent of the bilateral smoothing"),
               float_param("smoothing_range", 6.0, 0.5, 50.0, "",
                           "CIELAB colour difference (Delta E) the smoothing blurs across; larger edges stay"),
           }},
    [] { return std::make_unique<Cartoon>(); }}};

}  // namespace
}  // namespace pointnpr
