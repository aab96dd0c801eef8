// Flow-based oil paint after Semmo, Limberger, Kyprianidis and Doellner
// 2016 ("Image stylization by interactive oil paint filtering"):
//  - flow field: the smoothed structure tensor's edge direction (the
//    Kuwahara filter's passes, filters::structure_tensor);
//  - colour: a flow-aligned bilateral filter (Kyprianidis and Doellner
//    2008: across the edges along the gradient, then along the flow curve)
//    in Oklab, and the lightness gathered into soft bands, a palette of
//    lightnesses (the paper quantizes to a palette of the image's colours;
//    a palette per frame would differ between the tiles of one frame);
//  - paint texture: noise smeared by a line integral along the flow curves
//    (bristle streaks `brush_size` wide and `stroke_length` long), stopping
//    at colour edges, plus paint thickness from lightness, lit as a height
//    field (bump map with a Phong highlight, shaders/paint_relief.glsl).
// The noise is fixed to the surface: evaluated at each pixel's point in the
// segment's object space at powers of two of its units (as the watercolor's
// paper), so the strokes' texture stays on the scan when the camera moves;
// pixels without depth (gaps the gap fill closed) take the streaks of their
// neighbours along the flow. Only covered pixels are read or written, so
// the background never bleeds in and the outline stays where it was.
#include <algorithm>
#include <cmath>

#include "filters/filter_util.h"

namespace pointnpr {
namespace {

constexpr uint32_t kPaintSeed = 40u;  // one paint texture under every segment

// How far each stage reads, in px: the streaks along the flow (0 without
// relief), the bilateral filter each way, the tensor's smoothing.
struct Reach {
  int stroke, smooth, tensor;
};

Reach reach(const ParamValues& p) {
  const bool relief = p.get_float("impasto") > 0.0;
  // The bilateral kernels end at 2 sigma (95 % of a Gaussian's weight; the
  // range weights cut them shorter at edges anyway).
  return {relief ? int(std::ceil(0.5 * p.get_float("stroke_length"))) : 0,
          int(std::ceil(2.0 * p.get_float("smoothing"))), filters::gauss_radius(p.get_float("tensor_sigma"))};
}

// The rectangles each pass writes: the shading's rect, the height 1 px
// around it (central differences), the paint and noise the streaks read,
// the cross-edge pass the flow-curve pass reads, the Oklab colour it reads.
struct Areas {
  Rect height, paint, across, lab;
};

Areas areas(const FilterContext& ctx, const Reach& r) {
  Areas a;
  a.height = r.stroke > 0 ? ctx.rect.grown(1, ctx.image_size) : ctx.rect;
  a.paint = r.stroke > 0 ? a.height.grown(r.stroke + 1, ctx.image_size) : ctx.rect;
  a.across = a.paint.grown(r.smooth + 1, ctx.image_size);
  a.lab = a.across.grown(r.smooth + 1, ctx.image_size);
  return a;
}

void set_rect(const gl::Program& prog, const char* min_name, const char* max_name, const Rect& r) {
  glUniform2i(prog.location(min_name), r.min.x, r.min.y);
  glUniform2i(prog.location(max_name), r.max.x, r.max.y);
}

class FlowOil final : public Filter {
 public:
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    const Reach r = reach(p);
    return (r.stroke > 0 ? r.stroke + 2 : 0) + r.smooth + 1 + std::max(r.smooth + 1, r.tensor + 1);
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const Reach r = reach(p);
    const Areas a = areas(ctx, r);
    const gl::Texture& lab = ctx.scratch(0);  // also the tensor, then the noise
    const gl::Texture& across = ctx.scratch(1);  // also the tensor's x pass, then the height
    const gl::Texture& flow = ctx.scratch(2);
    const gl::Texture& paint = ctx.scratch(3);
    filters::structure_tensor(ctx, *ctx.input, a.across, r.tensor, float(p.get_float("tensor_sigma")), lab, across,
                              flow);
    const float sigma = float(p.get_float("smoothing"));
    const float tolerance = float(p.get_float("tolerance"));
    {
      const gl::Program& prog = ctx.shaders->compute("flow_oil.comp", {"PASS_LAB"});
      prog.use();
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(1, lab, GL_WRITE_ONLY);
      dispatch_rect(prog, a.lab);
    }
    struct Smoothing {
      const char* define;
      const gl::Texture *src, *dst;
      Rect valid, write;
    };
    for (const Smoothing& s : {Smoothing{"PASS_ACROSS", &lab, &across, a.lab, a.across},
                               Smoothing{"PASS_ALONG", &across, &paint, a.across, a.paint}}) {
      const gl::Program& prog = ctx.shaders->compute("flow_oil.comp", {s.define});
      prog.use();
      set_rect(prog, "u_valid_min", "u_valid_max", s.valid);
      set_rect(prog, "u_flow_min", "u_flow_max", a.across);
      glUniform1f(prog.location("u_sigma"), sigma);
      glUniform1i(prog.location("u_radius"), r.smooth);
      glUniform1f(prog.location("u_tolerance"), tolerance);
      glUniform1i(prog.location("u_levels"), p.get_int("levels"));
      glUniform1f(prog.location("u_band_sharpness"), float(p.get_float("band_sharpness")));
      filters::bind_image(4, *s.src, GL_READ_ONLY);
      filters::bind_image(5, flow, GL_READ_ONLY);
      filters::bind_image(1, *s.dst, GL_WRITE_ONLY);
      dispatch_rect(prog, s.write);
    }
    const float relief = float(p.get_float("impasto"));
    const gl::Texture& height = across;  // free again
    if (relief > 0.0f) paint_height(ctx, p, r, a, paint, flow, lab, height);
    const gl::Program& prog = ctx.shaders->compute("flow_oil.comp", {"PASS_SHADE"});
    prog.use();
    glUniform1i(prog.location("u_relief"), relief > 0.0f ? 1 : 0);
    glUniform1f(prog.location("u_gloss"), float(p.get_float("gloss")));
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    filters::bind_image(2, height, GL_READ_ONLY);
    filters::bind_image(6, paint, GL_READ_ONLY);
    dispatch_rect(prog, ctx.rect);
  }

 private:
  // The paint's height over a.height: surface-fixed noise over a.paint
  // (into `noise`), smeared along the flow.
  static void paint_height(const FilterContext& ctx, const ParamValues& p, const Reach& r, const Areas& a,
                           const gl::Texture& paint, const gl::Texture& flow, const gl::Texture& noise,
                           const gl::Texture& height) {
    const float brush = float(p.get_float("brush_size"));
    {
      const gl::Program& prog = ctx.shaders->compute("flow_oil.comp", {"PASS_NOISE"});
      prog.use();
      set_surface_uniforms(prog, ctx.surface);
      glUniform1f(prog.location("u_brush_size"), brush);
      glUniform1ui(prog.location("u_seed"), kPaintSeed);
      filters::bind_image(0, *ctx.input, GL_READ_ONLY);
      filters::bind_image(1, noise, GL_WRITE_ONLY);
      glBindImageTexture(2, ctx.raster_depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
      dispatch_rect(prog, a.paint);
    }
    const gl::Program& prog = ctx.shaders->compute("flow_oil.comp", {"PASS_HEIGHT"});
    prog.use();
    set_rect(prog, "u_valid_min", "u_valid_max", a.paint);
    set_rect(prog, "u_flow_min", "u_flow_max", a.across);
    glUniform1f(prog.location("u_sigma"), 0.5f * float(r.stroke));
    glUniform1i(prog.location("u_radius"), r.stroke);
    glUniform1f(prog.location("u_tolerance"), float(p.get_float("tolerance")));
    glUniform1f(prog.location("u_brush_size"), brush);
    glUniform1f(prog.location("u_ridge"), float(p.get_float("impasto")));
    filters::bind_image(4, noise, GL_READ_ONLY);
    filters::bind_image(5, flow, GL_READ_ONLY);
    filters::bind_image(6, paint, GL_READ_ONLY);
    filters::bind_image(1, height, GL_WRITE_ONLY);
    dispatch_rect(prog, a.height);
  }
};

const FilterRegistration registration{{
    Schema{"flow_oil",
           "Oil Paint (Flow)",
           "Oil paint whose strokes follow the image's flow: colours smoothed along the flow into a palette of "
           "lightnesses, bristle streaks lit as paint relief.",
           {
               float_param("tensor_sigma", 6.0, 0.5, 8.0, "px",
                           "Smoothing of the structure tensor: how far the strokes' direction averages the edges"),
               float_param("smoothing", 4.0, 0.5, 8.0, "px",
                           "Sigma of the flow-aligned bilateral filter, across the edges and along the flow"),
               float_param("tolerance", 0.1, 0.01, 0.5, "",
                           "Colour difference (Oklab) the smoothing blends and the streaks run over; larger ones are "
                           "edges that stay"),
               int_param("levels", 6, 0, 24, "", "Lightness bands the colours gather to (0 = none)"),
               only_when(float_param("band_sharpness", 6.0, 0.0, 20.0, "",
                                     "How flat the bands are: 0 keeps the smoothed lightness, more gives flat bands"),
                         "levels", {"nonzero"}),
               float_param("impasto", 0.04, 0.0, 1.0, "",
                           "Relief of the paint: the bristle ridges' height over their width, lit as a bump map "
                           "(0 = flat)"),
               only_when(float_param("brush_size", 2.0, 0.5, 8.0, "px",
                                     "Width of the bristle streaks (their noise is fixed to the surface)"),
                         "impasto", {"nonzero"}),
               only_when(float_param("stroke_length", 20.0, 2.0, 48.0, "px", "Length of the streaks along the flow"),
                         "impasto", {"nonzero"}),
               only_when(float_param("gloss", 0.3, 0.0, 1.0, "", "Specular highlight on the paint's ridges"),
                         "impasto", {"nonzero"}),
           }},
    [] { return std::make_unique<FlowOil>(); }}};

}  // namespace
}  // namespace pointnpr
