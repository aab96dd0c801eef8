#include "render/style.h"

#include <algorithm>

#include "core/error.h"

namespace pointnpr {

const Schema& inpaint_schema() {
  static const Schema schema{
      "inpaint",
      "Inpaint Depth",
      "Gives the pixels the filters drew a depth, so that filtered borders keep their place in front of or "
      "behind other segments (Wegen et al., Listing 1, made safe at depth discontinuities).",
      {
          enum_param("method", {"surface", "paper", "strict"}, 0,
                     "surface: pixels the points cover keep their depth, pixels the filters added take the "
                     "nearest surface's (no mean across depth jumps); paper: Listing 1, every pixel whose colour "
                     "changed takes the mean covered depth around it; strict: as surface, but paint beyond a "
                     "silhouette never covers another segment's points"),
          only_when(float_param("threshold", 0.02, 0.0, 1.0, "",
                                "Gray-level (or coverage) change above which a pixel counts as changed by the filters"),
                    "method", {"paper"}),
          int_param("radius", 4, 1, 64, "px", "Radius of the circle whose covered depths are used"),
          only_when(float_param("discontinuity", 0.03, 0.0, 1.0, "",
                                "Relative depth gap that separates two surfaces: an added pixel takes the mean of "
                                "the covered depths within this of the nearest one"),
                    "method", {"surface", "strict"}),
      }};
  return schema;
}

const Schema& composite_schema() {
  static const Schema schema{
      "composite",
      "Composite",
      "How the segments' images are combined into the frame.",
      {
          enum_param("mode", {"layering", "depth_test", "inpaint"}, 2,
                     "layering: segment order only; depth_test: rasterized depth; inpaint: depth after inpainting"),
      }};
  return schema;
}

MarkStep make_mark(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                   const std::map<std::string, std::string>& paths) {
  const MarkInfo& info = find_mark(id);
  MarkStep step;
  step.info = &info;
  step.params = validate(info.schema, params, paths);
  step.mark = info.create();
  return step;
}

void Style::set_mark(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                     const std::map<std::string, std::string>& paths) {
  if (id == "mesh_surface")
    throw ParameterError("mesh_surface draws a segment's meshes beside its point mark: give its parameters as the "
                         "style's surface, not as its mark");
  mark = make_mark(id, params, paths);
}

void Style::set_surface(const std::map<std::string, std::vector<double>>& params) {
  surface = make_mark("mesh_surface", params);
}

bool Style::fills_gaps() const {
  return mark.info->schema.id == "points" &&
         std::any_of(filters.begin(), filters.end(), [](const FilterStep& f) { return f.filter->reads_neighbourhood(); });
}

AttributeSet Style::attributes() const {
  AttributeSet set = mark.mark->attributes(mark.params);
  if (fills_gaps()) set.insert({AttributeKind::SplatRadius, kGapSpacingNeighbours});
  return set;
}

void Style::add_filter(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                       const std::map<std::string, std::string>& paths) {
  filters.push_back(make_filter_step(id, params, paths));
}

bool streams(const Segment& seg) {
  return std::any_of(seg.instances.begin(), seg.instances.end(), [](const Instance& i) { return bool(i.cached); });
}

ScanSampling segment_sampling(const Segment& seg, const std::vector<VisibleChunk>& frame_chunks, double depth_min) {
  ScanSampling out;
  // An out-of-core scan streams a new cloud whenever the view changes its
  // counts: its spacing would be a kNN of the streamed points per such
  // frame. Left unknown there (the filters' pixel rules), until the cache
  // keeps the spacing.
  if (streams(seg)) return out;
  const GpuCloud* last = nullptr;
  float last_scale = 0.0f;
  for (const VisibleChunk& v : frame_chunks) {
    // A cloud's chunks share its spacing; one look-up per cloud and scale.
    const float scale = view_scale(v);
    if (v.gpu == last && scale == last_scale) continue;
    last = v.gpu, last_scale = scale;
    // The largest: each cloud's own gaps close (depths still decide).
    out.spacing = std::max(out.spacing, view_spacing(v, kGapSpacingNeighbours));
  }
  out.depth_min = float(depth_min);
  return out;
}

}  // namespace pointnpr
