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

#include "marks/stipples/settings.h"
#include "render/mark.h"

namespace pointnpr {

constexpr int kStippleHistogramBins = 1024;  // log2 of the specular measure, 8 bins per octave (specular_bin)
constexpr int kStippleSpacingNeighbors = 8;  // a point's spacing: the mean distance to these nearest neighbours
constexpr int kStippleNormalNeighbors = 16;  // lit_rule share's normals (estimated once where a scan has none)
// spread_from_spacing: the most fine texels a point covers each way (half a
// spacing of 16 texels): bounds a point's writes and the tiles' halos.
constexpr int kStippleMaxSpread = 8;

// What the passes read that is fixed for a frame: the kernels' settings
// (shaders/stipples_settings.glsl: the camera's float projection, the fine
// texels' scale, the light frame in view space, the shading and dot
// parameters) and what only the passes' orchestration reads.
struct StippleSetup {
  const ParamValues* params = nullptr;  // the resolution queue's (draws_queue, queue_count)
  Rect clip;                            // the tile's pixels the mark draws (local; u.clip_min/max)
  int iterations = 0;
  double spread_scale = 0.0;  // spread_from_spacing: half the fine texels per scene unit at view depth 1
  double spacing_cell_scale = 0.0;  // level_scale spacing: a point's cell width over its spacing (2^(8 - LEVEL))
  bool opacity_draws = false;  // a dot only where id_rand(point id) < the splat's opacity (the dots pass)
  stipples::StippleSettings u{};

  // The visible points and covered texels per eye cell are counted for the
  // specular measure and for the tone (shaders/stipples_kernels.glsl).
  bool counts_eye() const { return u.specular != 0 || u.tone_scale > 0.0f; }
  // The points' spacing is read: for their levels, or for their spread.
  bool reads_spacing() const { return u.level_from_spacing != 0 || u.spread_max > 0; }
  // How far (fine texels) a point's depth reaches: its own spread and the iterations.
  int reach_texels() const { return iterations + u.spread_max; }
  // The light-view quadtree only where it is read (the share rule without cast shadows reads none).
  size_t quad_n() const { return u.quadtree ? (size_t(2) << u.levels) * (size_t(1) << u.levels) : 1; }
  size_t light_n() const { return u.specular ? size_t(u.light_cells) * size_t(u.light_cells) : 1; }
};

// A piece of the frame the hidden-point passes run over (frame pixels px)
// and its kernels' settings (shaders/stipples_settings.glsl's
// StippleWindowSettings); by default it owns every texel.
struct StippleWindow {
  Rect px;
  stipples::StippleWindowSettings k{{0, 0}, {0, 0}, glm::ivec2(std::numeric_limits<int>::min()),
                                    glm::ivec2(std::numeric_limits<int>::max()), {0, 0}, {1, 1}};
  size_t fine_n() const { return size_t(k.fine_size.x) * size_t(k.fine_size.y); }
  size_t eye_n() const { return size_t(k.eye_cells.x) * size_t(k.eye_cells.y); }
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

// A chunk's points' cell width over their spacing (its instance's scale
// applied), for lit_out's cell_target.
float spacing_cell_scale(const StippleSetup& s, const VisibleChunk& v);
// A chunk's spacing to spread_texels' scale (the view's scale of object lengths included).
float spread_scale(const StippleSetup& s, const VisibleChunk& v);
// The largest spacing a chunk's points spread (its cloud's sparse spacing; unbounded without one).
float spread_cap(const VisibleChunk& v);

// The captured mark of a dot drawn at `center` (view space) for point `id`.
CapturedMark captured_dot(const StippleSetup& s, glm::vec3 center, uint32_t id);

std::unique_ptr<StipplePasses> make_gl_stipple_passes(const MarkContext& ctx, const StippleSetup& s);
std::unique_ptr<StipplePasses> make_native_stipple_passes(const MarkContext& ctx, const StippleSetup& s);

}  // namespace pointnpr
