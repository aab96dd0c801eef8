// Colour grading of a segment: exposure in scene-linear light, then
// contrast, saturation and hue rotation in Oklab (perceptual, so a hue
// shift keeps lightness and saturation changes keep hue), then an optional
// 3-D look-up table image. Per pixel; background untouched.
//
// LUT images (read through OpenImageIO, display sRGB in and out):
//  - a strip, N² x N pixels: N slices of N x N side by side, blue across
//    slices, red across each slice, green downward; top-left is black
//    (Unreal Engine's colour-table layout);
//  - a Hald CLUT, L³ x L³ pixels: entry r + g N + b N² (N = L²) in reading
//    order, as Hald identity images made by ImageMagick or G'MIC.
// Both become the strip layout on the GPU; lookups are trilinear.
#include <cmath>

#include "core/error.h"
#include "core/image_io.h"
#include "filters/filter_util.h"
#include "render/image_textures.h"

namespace pointnpr {
namespace {

// Strip layout with row y = green (GL rows, bottom first), from either format.
Image lut_as_strip(Image file) {
  const int w = file.width, h = file.height;
  int n = 0;
  bool hald = false;
  if (h >= 2 && w == h * h) {
    n = h;
  } else if (w == h) {
    const int level = int(std::lround(std::cbrt(double(w))));
    if (level >= 2 && level * level * level == w) n = level * level, hald = true;
  }
  if (n == 0)
    throw Error("a LUT image is N²xN (strip) or L³xL³ (Hald CLUT), got " + std::to_string(w) + "x" +
                std::to_string(h));
  Image strip;
  strip.width = n * n;
  strip.height = n;
  strip.channels = 4;
  strip.pixels.resize(size_t(n) * size_t(n) * size_t(n) * 4);
  for (int b = 0; b < n; ++b)
    for (int g = 0; g < n; ++g)
      for (int r = 0; r < n; ++r) {
        // Source pixel in file (top-first) coordinates, then in GL rows.
        int x = 0, y_top = 0;
        if (hald) {
          const long i = long(r) + long(g) * n + long(b) * n * n;
          x = int(i % w), y_top = int(i / w);
        } else {
          x = b * n + r, y_top = g;
        }
        const float* src = &file.pixels[(size_t(h - 1 - y_top) * size_t(w) + size_t(x)) * 4];
        float* dst = &strip.pixels[(size_t(g) * size_t(n * n) + size_t(b * n + r)) * 4];
        for (int c = 0; c < 3; ++c) dst[c] = src[c];
        dst[3] = 1.0f;
      }
  return strip;
}

class ColorGrade final : public Filter {
 public:
  int footprint(const ParamValues&) const override { return 0; }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const std::string& lut_path = p.get_path("lut");
    const gl::Texture* lut = nullptr;
    if (!lut_path.empty())
      lut = &ctx.images->get(lut_path, "colour look-up table", ImageTextures::Sampling::Clamped, lut_as_strip);
    const gl::Program& prog = ctx.shaders->compute("color_grade.comp");
    prog.use();
    const double hue = p.get_float("hue_shift") * M_PI / 180.0;
    glUniform1f(prog.location("u_gain"), float(std::exp2(p.get_float("exposure"))));
    glUniform1f(prog.location("u_contrast"), float(p.get_float("contrast")));
    glUniform1f(prog.location("u_saturation"), float(p.get_float("saturation")));
    glUniform2f(prog.location("u_hue"), float(std::cos(hue)), float(std::sin(hue)));
    glUniform1f(prog.location("u_gamma"), float(p.get_float("gamma")));
    filters::set_color(prog, "u_tint", p.get_color("tint"));
    glUniform1f(prog.location("u_lut_size"), lut ? float(lut->size().y) : 0.0f);
    glUniform1f(prog.location("u_lut_strength"), float(p.get_float("lut_strength")));
    glBindTextureUnit(0, lut ? lut->id() : 0);
    glUniform1i(prog.location("u_lut"), 0);
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    dispatch_rect(prog, ctx.rect);
    glBindTextureUnit(0, 0);
  }
};

const FilterRegistration registration{{
    Schema{"color_grade",
           "Color Grade",
           "Exposure, contrast, saturation, hue shift, gamma, tint and a look-up table image for the segment's colours.",
           {
               float_param("exposure", 0.0, -10.0, 10.0, "EV", "Brightness in stops, applied in scene-linear light"),
               float_param("contrast", 1.0, 0.0, 4.0, "", "Lightness contrast around middle grey (1 = unchanged)"),
               float_param("saturation", 1.0, 0.0, 4.0, "", "Chroma scale (0 = grey, 1 = unchanged)"),
               float_param("hue_shift", 0.0, -180.0, 180.0, "deg", "Rotation of hues in Oklab"),
               float_param("gamma", 1.0, 0.1, 10.0, "", "Power on scene-linear light after exposure (1 = unchanged)"),
               color_param("tint", {1.0, 1.0, 1.0, 1.0},
                           "Multiplies scene-linear colour (white = unchanged; alpha unused)"),
               image_param("lut", "3-D look-up table applied last: a N²xN strip or a L³xL³ Hald CLUT image (display sRGB)"),
               float_param("lut_strength", 1.0, 0.0, 1.0, "", "Blend from the graded colour (0) to its look-up (1)"),
           }},
    [] { return std::make_unique<ColorGrade>(); }}};

}  // namespace
}  // namespace pointnpr
