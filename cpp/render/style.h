#pragma once
// A style is a segment's pipeline: one mark -> filters -> depth inpainting.
// The fixed stages declare their parameters like marks and filters do.
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/params.h"
#include "render/filter_chain.h"
#include "render/mark.h"
#include "scene/point_cloud.h"
#include "scene/triangle_mesh.h"

namespace pointnpr {

class CachedCloud;  // scene/cached_cloud.h

const Schema& inpaint_schema();
const Schema& composite_schema();

enum class CompositeMode { Layering = 0, DepthTest = 1, Inpaint = 2 };

struct MarkStep {
  const MarkInfo* info = nullptr;
  std::shared_ptr<const Mark> mark;
  ParamValues params;
};
MarkStep make_mark(const std::string& id, const std::map<std::string, std::vector<double>>& params = {},
                   const std::map<std::string, std::string>& paths = {});

struct Style {
  MarkStep mark = make_mark("points");
  // How the segment's objects with faces are drawn (marks/mesh_surface/mesh_surface.h):
  // as surfaces by default, or handed to `mark` as points.
  MarkStep surface = make_mark("mesh_surface");
  std::vector<FilterStep> filters;
  ParamValues inpaint = validate(inpaint_schema(), {});

  void set_mark(const std::string& id, const std::map<std::string, std::vector<double>>& params = {},
                const std::map<std::string, std::string>& paths = {});
  void set_surface(const std::map<std::string, std::vector<double>>& params = {});
  void add_filter(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                  const std::map<std::string, std::string>& paths = {});
  // The per-point attributes the mark reads (only those are computed and
  // uploaded, once per cloud), and the ones of them a host supplies.
  // With the gap fill, each point's spacing too (MarkTargets::spacing).
  AttributeSet attributes() const;
  // Whether the filter chain fills the gaps between the mark's splats (the
  // points mark before a filter that reads neighbourhoods).
  bool fills_gaps() const;
  std::vector<std::string> source_attributes() const { return source_attribute_names(attributes()); }
};

// One object of a segment: a cloud, or a triangle mesh (exactly one).
struct Instance {
  std::shared_ptr<const PointCloud> cloud;
  glm::dmat4 world_from_object{1.0};
  std::string name;  // the host's object name, for messages ("" = unnamed)
  std::shared_ptr<const TriangleMesh> mesh;  // last: {cloud, matrix} initialisers stay valid
  // An out-of-core scan: its points stream from the cache per frame
  // (render/streamed_cloud.h), in place of `cloud`.
  std::shared_ptr<const CachedCloud> cached;
};

struct Segment {
  std::string name;
  Style style;
  std::vector<Instance> instances;
};

// Whether a segment has an out-of-core scan (its points streamed per view).
bool streams(const Segment& seg);
// The segment's point spacing for its filters (render/filter.h
// ScanSampling), from the frame's chunks, so every tile gets the same.
ScanSampling segment_sampling(const Segment& seg, const std::vector<VisibleChunk>& frame_chunks, double depth_min);

struct Scene {
  std::vector<Segment> segments;  // order = layering order (later on top)
};

}  // namespace pointnpr
