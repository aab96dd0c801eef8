// Watercolor after Bousseau, Kaplan, Thollot and Sillion 2006 ("Interactive
// watercolor rendering with temporal coherence and abstraction") and the
// pigment effects of Curtis et al. 1997:
//  - abstraction: a coverage-normalized separable bilateral filter of the
//    colours (Bousseau uses mean shift; this keeps edges at GPU speed), at
//    half resolution (a 2x2 mean of the covered pixels first; the compose
//    reads it bilinearly);
//  - wobbling: the abstracted image is looked up through a smooth noise
//    displacement, so region borders turn irregular;
//  - edge darkening: pigment gathers at colour edges (where a plain blur of
//    the colours departs from the edge-keeping one) and along the border of
//    each wet region (its coverage falls off);
//  - wet-in-wet: in wet patches the colours of neighbouring washes run into
//    each other (a wide blur within the segment) and leave no hard edge;
//  - dispersion (low-frequency variation of pigment density) and granulation
//    (pigment settling in the paper's valleys), all through Bousseau's
//    density model C' = C - (C - C^2)(d - 1);
//  - dry brush (as in the real-time watercolor of Montesdeoca et al. 2017):
//    a dry brush leaves pigment only on the paper's peaks, most along region
//    borders, so the paper colour shows through in the valleys.
// Every noise is fixed to the surface, not to the screen: it is evaluated at
// the pixel's point in the segment's object space (SurfaceFrame and the
// raster depth; gaps and wobbled borders take the nearest surface's depth),
// at powers of two of the object's units cross-faded by distance (dynamic
// solid textures, Benard et al. 2009), so the paper and the pigment stay on
// the scan when the camera moves and keep their size on screen. The paper is
// smooth fractal gradient noise, or a height map image read through
// OpenImageIO (white = peaks) tiled on the axis planes of object space,
// weighted by the view direction. The slow fields (wobble, dispersion,
// wetness, the bleed colour) are evaluated once every 4 px and interpolated;
// only the paper grain is evaluated per pixel.
// Holes narrower than the edge width are painted over; lone points keep
// their colour (with pigment effects) and get no darkened rim.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "filters/filter_util.h"
#include "render/image_textures.h"

namespace pointnpr {
namespace {

struct Sizes {
  double sigma_abstract, sigma_fill;  // full-resolution pixels
  int kernel, wobble;                 // kernel: radius in half-resolution pixels
};

constexpr int kNode = 4;  // NODE in shaders/watercolor.comp: the slow fields' spacing
constexpr int kMaxRadius = 16;  // MAX_RADIUS there: the weights' array

Sizes sizes(const ParamValues& p) {
  Sizes s;
  s.sigma_abstract = p.get_float("abstraction");
  s.sigma_fill = 0.5 * p.get_float("edge_width");
  s.kernel = std::max(filters::gauss_radius(0.5 * s.sigma_abstract), filters::gauss_radius(0.5 * s.sigma_fill));
  s.wobble = int(std::ceil(p.get_float("wobble")));
  return s;
}

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Gaussian weights of the half-resolution kernel, k = 0..radius (sigma in
// full pixels; ~0 sigma: the centre only).
std::vector<float> half_weights(double sigma, int radius) {
  std::vector<float> w(kMaxRadius + 1, 0.0f);
  const double h = std::max(0.5 * sigma, 1e-3);
  for (int k = 0; k <= radius; ++k) w[size_t(k)] = float(std::exp(-double(k * k) / (2.0 * h * h)));
  return w;
}

class Watercolor final : public Filter {
 public:
  // Borders move by up to `wobble` px; the slow fields' nodes read the
  // abstracted image up to 2 nodes (+2 px) away; the half-resolution kernel
  // reaches 2 px per half pixel beyond, plus the 2x2 of the downsampling.
  bool reads_neighbourhood() const override { return true; }
  int footprint(const ParamValues& p) const override {
    const Sizes s = sizes(p);
    return s.wobble + 2 * kNode + 2 + 2 * s.kernel + 2;
  }

  void apply(const FilterContext& ctx, const ParamValues& p) const override {
    const Sizes s = sizes(p);
    const glm::ivec2 origin = pixel_origin();
    // The abstraction runs at half resolution on frame pixel pairs (so tiles
    // match the frame): half pixel h covers frame pixels 2h and 2h + 1. Its
    // images hold half pixels [half_lo - r, half_hi + r) from index 0; the
    // abstracted ones are valid on [r, n + r).
    const Rect abstract_rect = ctx.rect.grown(s.wobble + 2 * kNode + 2, ctx.image_size);
    const int r = s.kernel;
    const glm::ivec2 half_lo{floor_div(origin.x + abstract_rect.min.x, 2), floor_div(origin.y + abstract_rect.min.y, 2)};
    const glm::ivec2 half_hi{floor_div(origin.x + abstract_rect.max.x - 1, 2) + 1,
                             floor_div(origin.y + abstract_rect.max.y - 1, 2) + 1};
    const glm::ivec2 n = half_hi - half_lo;
    const glm::ivec2 half_min = half_lo - r;
    const Rect valid{{r, r}, n + r};
    const gl::Texture& down = ctx.scratch(0);
    const gl::Texture& sums_a = ctx.scratch(1);
    const gl::Texture& sums_b = ctx.scratch(2);
    const gl::Texture& abstract = ctx.scratch(3);
    const gl::Texture& plain = ctx.scratch(4);
    const std::vector<float> ws = half_weights(s.sigma_abstract, r), wf = half_weights(s.sigma_fill, r);
    double norm = wf[0];
    for (int k = 1; k <= r; ++k) norm += 2.0 * wf[size_t(k)];
    for (const char* pass : {"PASS_DOWN", "PASS_ABSTRACT_X", "PASS_ABSTRACT_Y"}) {
      const gl::Program& prog = ctx.shaders->compute("watercolor.comp", {pass});
      prog.use();
      glUniform2i(prog.location("u_half_min"), half_min.x, half_min.y);
      glUniform1i(prog.location("u_radius"), r);
      glUniform1fv(prog.location("u_w_abstract"), kMaxRadius + 1, ws.data());
      glUniform1fv(prog.location("u_w_fill"), kMaxRadius + 1, wf.data());
      glUniform1f(prog.location("u_tolerance"), float(p.get_float("abstraction_tolerance")));
      glUniform1f(prog.location("u_fill_norm"), float(norm * norm));
      const std::string which = pass;
      if (which == "PASS_DOWN") {
        filters::bind_image(0, *ctx.input, GL_READ_ONLY);
        filters::bind_image(1, down, GL_WRITE_ONLY);
        dispatch_rect(prog, Rect{{0, 0}, n + 2 * r});
      } else if (which == "PASS_ABSTRACT_X") {
        filters::bind_image(0, down, GL_READ_ONLY);
        filters::bind_image(2, sums_a, GL_WRITE_ONLY);
        filters::bind_image(3, sums_b, GL_WRITE_ONLY);
        dispatch_rect(prog, Rect{{r, 0}, {n.x + r, n.y + 2 * r}});
      } else {
        filters::bind_image(4, sums_a, GL_READ_ONLY);
        filters::bind_image(5, sums_b, GL_READ_ONLY);
        filters::bind_image(1, abstract, GL_WRITE_ONLY);
        filters::bind_image(3, plain, GL_WRITE_ONLY);
        dispatch_rect(prog, valid);
      }
    }
    // The slow fields, one node every kNode frame pixels over the rect
    // grown by a node (bilinear lookups) and the wobble.
    const int g = s.wobble + kNode + 1;
    const glm::ivec2 node_min{floor_div(origin.x + ctx.rect.min.x - g, kNode),
                              floor_div(origin.y + ctx.rect.min.y - g, kNode)};
    const glm::ivec2 node_max{floor_div(origin.x + ctx.rect.max.x - 1 + g, kNode) + 2,
                              floor_div(origin.y + ctx.rect.max.y - 1 + g, kNode) + 2};
    const gl::Texture& fields = ctx.scratch(0);
    const gl::Texture& bleed = ctx.scratch(1);
    const uint32_t seed = uint32_t(p.get_int("seed"));
    auto set_half = [&](const gl::Program& prog) {
      glUniform2i(prog.location("u_half_min"), half_min.x, half_min.y);
      glUniform2i(prog.location("u_abs_min"), valid.min.x, valid.min.y);
      glUniform2i(prog.location("u_abs_max"), valid.max.x, valid.max.y);
    };
    {
      const gl::Program& prog = ctx.shaders->compute("watercolor.comp", {"PASS_FIELDS"});
      prog.use();
      set_surface_uniforms(prog, ctx.surface);
      set_half(prog);
      glUniform2i(prog.location("u_node_min"), node_min.x, node_min.y);
      glUniform1ui(prog.location("u_seed"), seed);
      glUniform1f(prog.location("u_wobble_scale"), float(p.get_float("wobble_scale")));
      glUniform1f(prog.location("u_density_scale"), float(p.get_float("density_scale")));
      glBindImageTexture(2, ctx.raster_depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
      filters::bind_image(3, fields, GL_WRITE_ONLY);
      filters::bind_image(5, bleed, GL_WRITE_ONLY);
      filters::bind_image(6, plain, GL_READ_ONLY);
      dispatch_rect(prog, Rect{{0, 0}, node_max - node_min});
    }
    const std::string& paper_path = p.get_path("paper");
    const gl::Texture* paper = nullptr;
    if (!paper_path.empty())
      paper = &ctx.images->get(paper_path, "paper", ImageTextures::Sampling::Tiled, [](Image i) { return i; });
    // The paper image lies on the planes of object space facing the view most.
    const glm::vec3 view = glm::normalize(glm::vec3(ctx.surface.object_from_view * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
    glm::vec3 planes = glm::abs(view);
    planes = planes * planes * planes * planes;
    planes /= planes.x + planes.y + planes.z;
    const gl::Program& prog = ctx.shaders->compute("watercolor.comp", {"PASS_COMPOSE"});
    prog.use();
    set_surface_uniforms(prog, ctx.surface);
    set_half(prog);
    glBindTextureUnit(0, paper ? paper->id() : 0);
    glUniform1i(prog.location("u_paper"), 0);
    glUniform1i(prog.location("u_paper_image"), paper ? 1 : 0);
    glUniform3f(prog.location("u_plane_weights"), planes.x, planes.y, planes.z);
    glUniform2i(prog.location("u_node_min"), node_min.x, node_min.y);
    glUniform1f(prog.location("u_dry_brush"), float(p.get_float("dry_brush")));
    filters::set_color(prog, "u_paper_color", p.get_color("paper_color"));
    glUniform1f(prog.location("u_wobble"), float(p.get_float("wobble")));
    glUniform1f(prog.location("u_edge_darkening"), float(p.get_float("edge_darkening")));
    glUniform1f(prog.location("u_density"), float(p.get_float("pigment_density")));
    glUniform1f(prog.location("u_granulation"), float(p.get_float("granulation")));
    glUniform1f(prog.location("u_wet"), float(p.get_float("wet_in_wet")));
    glUniform1f(prog.location("u_paper_scale"), float(p.get_float("paper_scale")));
    glUniform1ui(prog.location("u_seed"), seed);
    filters::bind_image(0, *ctx.input, GL_READ_ONLY);
    filters::bind_image(1, *ctx.output, GL_WRITE_ONLY);
    glBindImageTexture(2, ctx.raster_depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    filters::bind_image(3, fields, GL_READ_ONLY);
    filters::bind_image(4, abstract, GL_READ_ONLY);
    filters::bind_image(5, bleed, GL_READ_ONLY);
    filters::bind_image(6, plain, GL_READ_ONLY);
    dispatch_rect(prog, ctx.rect);
    glBindTextureUnit(0, 0);
  }
};

const FilterRegistration registration{{
    Schema{"watercolor",
           "Watercolor",
           "Abstracted washes with wobbly borders, darkened edges, wet-in-wet bleeding, pigment dispersion and paper "
           "granulation, fixed to the surface.",
           {
               float_param("abstraction", 2.0, 0.0, 8.0, "px", "Spatial sigma of the edge-preserving blur before painting"),
               float_param("abstraction_tolerance", 0.15, 0.01, 1.0, "",
                           "Colour difference (sRGB) the abstraction blurs across; colour edges above it stay"),
               float_param("wobble", 2.0, 0.0, 8.0, "px", "How far the paper displaces region borders"),
               float_param("wobble_scale", 24.0, 4.0, 256.0, "px", "Feature size of the border wobble"),
               float_param("edge_darkening", 1.0, 0.0, 2.0, "", "Pigment gathered at colour edges and region borders"),
               float_param("edge_width", 3.0, 1.0, 12.0, "px",
                           "Width of the darkened rim; holes narrower than this are painted over"),
               float_param("pigment_density", 0.3, 0.0, 1.0, "",
                           "Dispersion: low-frequency variation of pigment density, fixed to the surface"),
               float_param("density_scale", 64.0, 4.0, 512.0, "px", "Feature size of the density variation"),
               float_param("granulation", 0.3, 0.0, 1.0, "", "Pigment settling in the paper grain"),
               float_param("wet_in_wet", 0.5, 0.0, 1.0, "",
                           "Wet-in-wet: in wet patches (sized by density_scale) neighbouring colours run into each "
                           "other within the segment, without darkened edges"),
               float_param("dry_brush", 0.0, 0.0, 1.0, "",
                           "Dry brush: pigment only on the paper's peaks, most along region borders"),
               only_when(color_param("paper_color", {0.98, 0.97, 0.94, 1.0}, "Paper showing through a dry brush (display sRGB)"),
                         "dry_brush", {"nonzero"}),
               image_param("paper", "Paper height map (grey, white = peaks), tiled on the surface; none = procedural paper"),
               float_param("paper_scale", 3.0, 1.0, 16.0, "px", "Paper grain size on screen: pixels per texel of the image, or the finest procedural feature"),
               int_param("seed", 0, 0, 65535, "", "Paper texture seed (same paper under every segment)"),
           }},
    [] { return std::make_unique<Watercolor>(); }}};

}  // namespace
}  // namespace pointnpr
