#pragma once
// The stipples mark's passes (seed 003; cpp/marks/stipples/stipples.cpp decides
// what runs over which window of the frame), behind one interface with two
// implementations: the GL compute passes of shaders/stipples.comp
// (marks/stipples/gl.cpp, for GPUs) and the same rules on the CPU's threads
// (marks/stipples/native.cpp, for software GL, where llvmpipe's per-texel passes
// and atomics cost several times a plain loop). Both make the same
// decisions from the same numbers below.
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "render/mark.h"

namespace pointnpr {

constexpr int kStippleHistogramBins = 1024;  // log2 of the specular measure, 8 bins per octave
// The bins' edges within an octave, 2^(k/8) for k = 1..7 as float bits (the
// same constants as shaders/stipples.comp's specular_bin).
constexpr uint32_t kStippleBinEdgeBits[7] = {0x3f8b95c2u, 0x3f9837f0u, 0x3fa5fed7u, 0x3fb504f3u,
                                             0x3fc5672au, 0x3fd744fdu, 0x3feac0c7u};

// Everything the passes read that is fixed for a frame (the shader's
// uniforms): the camera's float projection, the fine texels' scale, the
// light frame in view space, the shading and dot parameters.
struct StippleSetup {
  const ParamValues* params = nullptr;  // the resolution queue's (draws_queue, queue_count)
  glm::mat4 projection{1.0f};
  glm::ivec2 frame_px{0, 0};   // the whole frame's size (the projection maps to it)
  glm::ivec2 origin_px{0, 0};  // the tile's corner in the frame
  Rect clip;                   // the tile's pixels the mark draws (local)
  float near = 0.0f, far = 0.0f;
  bool ortho = false;
  float px_per_unit = 1.0f;  // pixels per scene unit at view depth 1
  float factor = 1.0f;       // fine texels per pixel
  int iterations = 0;
  float offset = 0.0f;  // depth added per spreading step, scene units
  // Light: orthographic along `light_dir` (towards the light, view space).
  glm::vec3 light_dir{0.0f, 0.0f, 1.0f}, light_right{1.0f, 0.0f, 0.0f}, light_up{0.0f, 1.0f, 0.0f};
  glm::vec2 light_origin{0.0f};  // (right, up) of the light texture's corner
  float light_extent = 1.0f;     // its side, scene units
  bool diffuse = false, casters_all = true;
  int levels = 1;  // n: the quadtree's finest level is 2^n x 2^n
  int level_lo = 0;
  float level_frac = 0.0f;
  bool specular = false;
  float tau = 0.0f;
  float eye_cell = 8.0f;  // pixels
  int light_cells = 1;    // per side
  float dot_size = 2.0f, size_jitter = 0.0f;
  uint32_t seed = 0;
  glm::vec4 dot_color{0.0f, 0.0f, 0.0f, 1.0f}, paper{1.0f};
  bool capture = false;

  size_t quad_n() const { return diffuse ? (size_t(2) << levels) * (size_t(1) << levels) : 1; }
  size_t light_n() const { return specular ? size_t(light_cells) * size_t(light_cells) : 1; }
};

// A piece of the frame the hidden-point passes run over: its fine texture
// (frame texels [fine_min, fine_min + fine)), its eye cells, and the fine
// texels whose points it counts for the frame (each point in exactly one
// window's; the rest of the window is the halo its decisions read).
struct StippleWindow {
  Rect px;  // frame pixels
  glm::ivec2 fine_min{0, 0}, fine{0, 0};
  glm::ivec2 owned_min{std::numeric_limits<int>::min()}, owned_max{std::numeric_limits<int>::max()};
  glm::ivec2 eye_min{0, 0}, eye_cells{1, 1};
  size_t fine_n() const { return size_t(fine.x) * size_t(fine.y); }
  size_t eye_n() const { return size_t(eye_cells.x) * size_t(eye_cells.y); }
};

// What the frame's tiles share, computed at its first tile from every
// visible point (bounded by the quadtree's and the light cells' caps, not by
// the frame's pixels).
struct StippleFrameState final : MarkFrameCache {
  std::vector<uint32_t> quad;         // the reduced quadtree (diffuse)
  std::vector<uint32_t> light_count;  // visible points per light cell (specular)
  float spec_ref = 1.0f;
};

// The passes, in the order stipples.cpp runs them. The frame's state (the
// quadtree, the light cells' counts, the specular histogram) starts empty
// and accumulates over windows; a window's images live until the next
// hidden_points().
class StipplePasses {
 public:
  virtual ~StipplePasses() = default;
  // Every caster (all points within the clip depths) of `chunks` into the
  // quadtree's finest level, with no window (tiles, before their windows).
  virtual void project_casters(std::span<const VisibleChunk> chunks) = 0;
  // 1. One window's hidden points: `chunks` into its min-depth texture
  // (and, with `casters`, every caster into the quadtree), spread; then its
  // visible points counted per eye cell and, with `for_frame`, into the
  // frame's counts where it owns them (visible casters, light cells). With
  // `surface`, also the visible points' surface for the paper. visible()
  // counts the visible points it owns.
  virtual void hidden_points(const StippleWindow& w, std::span<const VisibleChunk> chunks, bool for_frame,
                             bool casters, bool surface) = 0;
  // The last window's covered fine texels per eye cell (the closing).
  virtual void cover() = 0;
  virtual void reduce_quadtree() = 0;
  // The specular measure of the last window's owned visible points, into the histogram.
  virtual void specular_histogram(std::span<const VisibleChunk> chunks) = 0;
  virtual std::vector<uint32_t> histogram() = 0;
  virtual void save(StippleFrameState& state) = 0;
  virtual void load(const StippleFrameState& state) = 0;
  virtual uint32_t visible() = 0;
  // 4. The dots of the last window's visible points that stay, with their
  // captured marks; returns how many. Then the dots over the paper into the
  // mark's images over the clip.
  virtual uint32_t draw_dots(std::span<const VisibleChunk> chunks, float spec_ref,
                             std::vector<CapturedMark>* capture) = 0;
  virtual void resolve() = 0;
};

// The captured mark of a dot drawn at `center` (view space) for point `id`.
CapturedMark captured_dot(const StippleSetup& s, glm::vec3 center, uint32_t id);

std::unique_ptr<StipplePasses> make_gl_stipple_passes(const MarkContext& ctx, const StippleSetup& s);
std::unique_ptr<StipplePasses> make_native_stipple_passes(const MarkContext& ctx, const StippleSetup& s);

}  // namespace pointnpr
