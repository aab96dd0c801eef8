#pragma once
// A segment's image filters in order, ping-ponging two images; each
// filter's rect is its input's grown by its footprint, so the cost follows
// the segment's coverage, not the frame size. Used by the Renderer and by
// the filter test harness.
#include <functional>
#include <memory>
#include <vector>

#include "core/params.h"
#include "render/filter.h"

namespace pointnpr {

struct FilterStep {
  const FilterInfo* info = nullptr;
  std::shared_ptr<const Filter> filter;
  ParamValues params;
};
FilterStep make_filter_step(const std::string& id, const std::map<std::string, std::vector<double>>& params = {},
                            const std::map<std::string, std::string>& paths = {});

struct FilterChainImages {
  gl::ShaderLibrary* shaders = nullptr;
  ImageTextures* images = nullptr;
  const gl::Texture* first = nullptr;   // holds the chain's input
  const gl::Texture* second = nullptr;  // the other image of the ping-pong
  const gl::Texture* raster_depth = nullptr;
  std::function<const gl::Texture&(int index)> scratch;
  glm::ivec2 image_size{0, 0};
  double time = 0.0;
  uint32_t segment_seed = 0;
  SurfaceFrame surface;
  ScanSampling sampling;
  // Close the gaps between splats before the first filter that reads
  // neighbourhoods (shaders/gap_fill.comp), into `gap_image`: for point
  // splats, not for marks whose gaps are the drawing (strokes, stipples).
  bool fill_gaps = true;
  std::function<const gl::Texture&()> gap_image;
  // The gap-filled depths (R32F): the filters after the fill read them, so a
  // filled pixel lies on its surface (eye-dome lighting sees no pit there).
  std::function<const gl::Texture&()> gap_depth_image;
  // Each covered pixel's point's spacing, view units (the points mark's
  // SplatRadius, MarkTargets::spacing; 0 where unknown), or null: the fill
  // then knows the segment's spacing only.
  const gl::Texture* raster_spacing = nullptr;
};

// Runs `steps` from `rect` (the input's covered bounds); returns the image
// holding the result (`first` when there are no steps) and leaves `rect` at
// the last filter's rect.
const gl::Texture* run_filter_chain(const std::vector<FilterStep>& steps, const FilterChainImages& images, Rect& rect);

// How far the gap fill searches from a gap pixel for the surface around it,
// in pixels: twice the scan's spacing at the segment's nearest depth (gaps
// wider than that are holes in the scan), at least kGapSplatReach and at
// most kGapReachMax. Where each pixel's point's own spacing is known the
// search may reach kGapReachMax instead, narrowed per pixel by the spacing
// of the points its lines meet.
int gap_fill_reach(const ScanSampling& sampling, const SurfaceFrame& surface);
// The reach of the fill's other rule (gaps between splats as wide as the gap
// close, where the scan is sparser than its spacing or the spacing is
// unknown): gaps up to 15 px, the fill's reach before it knew the spacing.
constexpr int kGapSplatReach = 8;
// A bound on the gap fill's cost per gap pixel (8 directions of this many
// loads) and on the tiles' halo it adds (render/renderer.cpp).
// At most a 16x16 tile, so that a gap's ends lie in its tile or the 8
// around it (shaders/gap_fill.comp bounds each tile's search by theirs).
constexpr int kGapReachMax = 16;
// The fill's second stage (gaps among lone splats, shaders/
// gap_fill_pyramid.comp) pools cells of 2 to 2^kGapLevels px, and reads
// around a pixel the 3x3 coarsest cells about its own: that far beyond
// the line search. The tiles' halo adds it: kGapReachMax + kGapPushReach
// + 1 (render/renderer.cpp) is what a pixel's fill depends on (the cells,
// the line search behind their pixels, and the pinholes' two passes after
// within a pixel), to the pixel; a larger reach must grow it.
constexpr int kGapLevels = 4;
constexpr int kGapPushReach = 2 << kGapLevels;
// The neighbours a point's spacing is the mean distance to (the segment's,
// ScanSampling, and each point's, MarkTargets::spacing).
constexpr int kGapSpacingNeighbours = 8;

// Sum of the filters' footprints: how far the chain can reach beyond its input.
int total_footprint(const std::vector<FilterStep>& steps);

}  // namespace pointnpr
