#pragma once
// Image filters of a segment's pipeline. A filter is one .cpp in filters/
// that declares its Schema and registers itself, plus its GLSL in shaders/.
//
// Images handed to filters are RGBA32F, straight alpha, display-referred
// sRGB values in [0,1]; alpha is coverage (0 = background). Filters process
// only `ctx.rect` (the segment's screen bounds grown by the footprints of the
// filters so far), and may read up to their own footprint beyond it.
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/params.h"
#include "gl/objects.h"
#include "gl/shaders.h"
#include "render/registry.h"

namespace pointnpr {

class ImageTextures;  // render/image_textures.h
// One cache for filter runs outside a Renderer (tests, benchmarks); GL thread only.
ImageTextures& standalone_image_textures();

// Pixel rectangle [min, max) in image coordinates (row 0 = bottom).
struct Rect {
  glm::ivec2 min{0, 0};
  glm::ivec2 max{0, 0};
  bool empty() const { return max.x <= min.x || max.y <= min.y; }
  glm::ivec2 size() const { return glm::max(max - min, glm::ivec2(0)); }
  Rect grown(int by, glm::ivec2 limit) const;
  Rect united(const Rect& o) const;
};

struct Camera;  // scene/camera.h

// Where each pixel's surface point is, for filters that anchor patterns to
// the surface instead of the screen (so they do not slide when the camera
// moves). For the pixel centre q = (px, py, 1) (pixels, row 0 = bottom) at
// linear view depth d, the view-space point is
//   (dot(x0, q) + d dot(x1, q), dot(y0, q) + d dot(y1, q), -d),
// and object_from_view takes it to the segment's anchor frame: its first
// instance's object space, relative to that cloud's centre (composed in
// double, so float holds at any georeferenced offset).
struct SurfaceFrame {
  glm::vec3 x0{0.0f}, x1{0.0f}, y0{0.0f}, y1{0.0f};
  glm::mat4 object_from_view{1.0f};
};
SurfaceFrame make_surface_frame(const Camera& camera, glm::ivec2 image_size, const glm::dmat4& world_from_anchor);

// The scan's own sampling, handed to the filters that must tell its gaps
// and noise from the picture (the gap fill, eye-dome lighting, depth
// lines): one per segment and frame, the same in every tile.
struct ScanSampling {
  // The spacing of the segment's points in view units: the 90th percentile
  // of their mean distance to their 8 nearest neighbours
  // (LocalResolution::sparse_r, cached per cloud), the largest over the
  // segment's visible clouds; 0 = unknown (then filters keep their pixel
  // constants).
  float spacing = 0.0f;
  // The segment's nearest linear depth in the frame: where that spacing
  // spans the most pixels.
  float depth_min = 0.0f;
};

struct FilterContext {
  gl::ShaderLibrary* shaders = nullptr;
  ImageTextures* images = nullptr;         // image files the filters sample
  const gl::Texture* input = nullptr;      // color after the previous step
  const gl::Texture* output = nullptr;     // where this filter writes
  const gl::Texture* raster_depth = nullptr;  // linear view depth, +inf = empty
  // Scratch images of the same size for multi-pass filters (contents
  // undefined on entry; valid wherever the filter writes them).
  std::function<const gl::Texture&(int index)> scratch;
  Rect rect;                 // pixels this filter must write
  glm::ivec2 image_size{0, 0};
  double time = 0.0;         // scene time in seconds (animation)
  uint32_t segment_seed = 0; // stable per segment, for noise
  SurfaceFrame surface;      // with raster_depth: surface points (see above)
  ScanSampling sampling;     // the segment's point spacing (see above)
};

class Filter {
 public:
  virtual ~Filter() = default;
  // How many pixels beyond its input's covered area the filter can write
  // (and read): the segment's rect is grown by this before the filter runs.
  virtual int footprint(const ParamValues& params) const = 0;
  virtual void apply(const FilterContext& ctx, const ParamValues& params) const = 0;
  // Whether the filter reads its neighbours' colours (smoothing, edges,
  // paper): the chain then closes the gaps between the splats first
  // (depth-aware, shaders/gap_fill.comp), so it never sees background
  // inside a surface.
  virtual bool reads_neighbourhood() const { return false; }
};


struct FilterInfo {
  static constexpr const char* kKind = "filter";
  Schema schema;
  std::function<std::unique_ptr<Filter>()> create;
};

// All filters linked into the core, sorted by id.
const std::vector<const FilterInfo*>& registered_filters();
const FilterInfo& find_filter(const std::string& id);  // throws ParameterError

// Used by each filter's .cpp: `const FilterRegistration reg{{schema, factory}};`
using FilterRegistration = Registration<FilterInfo>;

// Dispatches `program` (local size 16x16, uniform ivec2 u_rect_min and
// u_rect_max) over `rect`, setting u_origin (shaders/common.glsl) to
// pixel_origin().
void dispatch_rect(const gl::Program& program, const Rect& rect);

// The frame pixel of the images' (0, 0): the tile's origin while the
// renderer draws a frame in tiles (render/tiling.h), else (0, 0). Shaders
// seed noise and place patterns by the frame pixel (local + u_origin), so a
// tile draws the same bytes as the whole frame. GL thread only.
glm::ivec2& pixel_origin();

// Sets the uniforms of surface_point() (shaders/filter_common.glsl).
void set_surface_uniforms(const gl::Program& program, const SurfaceFrame& frame);

}  // namespace pointnpr
