// XDoG edges (Winnemoeller, Kyprianidis and Olsen 2012): the extended
// difference of Gaussians (1+p) G_sigma - p G_{1.6 sigma} on perceptual
// lightness, soft-thresholded at epsilon with steepness phi, drawn in an
// edge colour over the image (or alone), plus the segment's silhouette.
//
// Gaussians are taken over covered pixels only (normalized convolution), so
// background and holes between points never make edges; the silhouette is
// drawn only around "solid" regions (covered with enough covered
// neighbours, or holes surrounded by points), so lone points get no rings.
//
// With `flow_length` > 0 the lines follow the image's flow (FDoG: Kang, Lee
// and Chui 2007, separable as in Kyprianidis and Doellner 2008): the
// structure tensor's edge direction (the Kuwahara filter's passes,
// shaders/kuwahara.comp) guides a 1-D DoG across the edges, which is then
// smoothed along the flow curves (a Gaussian line integral of sigma
// flow_length): coherent, unbroken lines where the isotropic DoG breaks
// into dots on scan noise.
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
  int flow, dog, tensor;  // FDoG: flow curve half length, DoG reach across edges, tensor smoothing (px); flow 0 = off
};

Radii radii(const ParamValues& p) {
  Radii r;
  r.sigma = std::max(0.5, 0.5 * p.get_float("thickness"));
  r.fill_sigma = 0.5 * p.get_int("fill_gaps");
  r.outline = p.get_bool("outline") ? int(std::ceil(p.get_float("thickness"))) : 0;
  r.kernel = std::max(filters::gauss_radius(kSurround * r.sigma), filters::gauss_radius(r.fill_sigma));
  r.flow = filters::gauss_radius(p.get_float("flow_length"));
  r.dog = filters::gauss_radius(kSurround * r.sigma);
  r.tensor = filters::gauss_radius(p.get_float("tensor_sigma"));
  return r;
}

// How far the FDoG reads beyond the pixels it draws: along the flow, then
// across the edges (plus a pixel of bilinear lookup each), the tensor's
// smoothing and its Sobel pixel.
int flow_reach(const Radii& r) { return r.flow == 0 ? 0 : r.flow + 1 + r.dog + 1 + r.tensor + 1;
}

class XDoG final : public Filter {
 public:
  // Draws the outline up to `thickness` px outside; reads the kernel beyond.
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    const Radii r = radii(p);
    return r.outline + std::max(r.kernel, flow_reach(r));
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
    const gl::Texture* flow = r.flow > 0 ? &flow_dog(ctx, p, r, sums_rect) : nullptr;
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
    glUniform1i(prog.location("u_flow"), flow ? 1 : 0);
    filters::bind_image(6, flow ? *flow : a1, GL_READ_ONLY);
    dispatch_rect(prog, ctx.rect);
  }

 private:
  // The FDoG response (u, coverage) over `area`, in scratch(1).
  static const gl::Texture& flow_dog(const FilterContext& ctx, const ParamValues& p, const Radii& r, const Rect& area) {
    const Rect along = area.grown(r.flow + 1, ctx.image_size);     // the DoG across edges, read along the flow
    const Rect lightness = along.grown(r.dog + 1, ctx.image_size);  // the lightness it samples
    const gl::Texture& L = ctx.scratch(4);
    const gl::Texture& tensor = ctx.scratch(0);  // free after the blur passes
    const gl::Texture& smooth_x = ctx.scratch(1);
    const gl::Texture& smooth = ctx.scratch(5);
    const gl::Texture& dog = ctx.scratch(0);
    const gl::Texture& out = ctx.scratch(1);
    const gl::Program& lp = ctx.shaders->compute("xdog.comp", {"PASS_LIGHTNESS"});
    lp.use();
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(2, L, GL_WRITE_ONLY);
    dispatch_rect(lp, lightness);
    // The edge direction: the Kuwahara filter's structure tensor passes.
    filters::structure_tensor(ctx, *ctx.input, along, r.tensor, float(p.get_float("tensor_sigma")), tensor, smooth_x,
                              smooth);
    for (const char* define : {"PASS_FDOG_ACROSS", "PASS_FDOG_ALONG"}) {
      const bool across = std::string(define) == "PASS_FDOG_ACROSS";
      const gl::Program& prog = ctx.shaders->compute("xdog.comp", {define});
      prog.use();
      glUniform1f(prog.location("u_sigma"), float(r.sigma));
      glUniform1f(prog.location("u_p"), float(p.get_float("sharpen")));
      glUniform1i(prog.location("u_radius"), across ? r.dog : r.flow);
      glUniform1f(prog.location("u_flow_sigma"), float(std::max(p.get_float("flow_length"), 1e-3)));
      glUniform2i(prog.location("u_valid_min"), across ? lightness.min.x : along.min.x, across ? lightness.min.y : along.min.y);
      glUniform2i(prog.location("u_valid_max"), across ? lightness.max.x : along.max.x, across ? lightness.max.y : along.max.y);
      glUniform2i(prog.location("u_flow_min"), along.min.x, along.min.y);
      glUniform2i(prog.location("u_flow_max"), along.max.x, along.max.y);
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(4, across ? L : dog, GL_READ_ONLY);
      filters::bind_image(5, smooth, GL_READ_ONLY);
      filters::bind_image(2, across ? dog : out, GL_WRITE_ONLY);
      dispatch_rect(prog, across ? along : area);
    }
    return out;
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
               float_param("flow_length", 0.0, 0.0, 12.0, "px",
                           "FDoG: smooth the lines along the image's flow over this sigma (0 = isotropic XDoG)"),
               only_when(float_param("tensor_sigma", 2.0, 0.5, 8.0, "px",
                                     "FDoG: smoothing of the structure tensor that gives the flow"),
                         "flow_length", {"nonzero"}),
           }},
    [] { return std::make_unique<XDoG>(); }}};

}  // namespace
}  // namespace pointnpr
