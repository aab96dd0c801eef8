#pragma once
// A style is a segment's pipeline: rasterize -> filters -> depth inpainting.
// The three fixed stages declare their parameters like filters do.
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/params.h"
#include "render/filter.h"
#include "scene/point_cloud.h"

namespace pointnpr {

const Schema& rasterize_schema();
const Schema& inpaint_schema();
const Schema& composite_schema();

enum class ColorSource { Rgb = 0, Intensity = 1, Classification = 2, Constant = 3 };
enum class SizeMode { Pixels = 0, World = 1 };
enum class CompositeMode { Layering = 0, DepthTest = 1, Inpaint = 2 };

struct FilterStep {
  const FilterInfo* info = nullptr;
  std::shared_ptr<const Filter> filter;
  ParamValues params;
};

struct Style {
  ParamValues rasterize = validate(rasterize_schema(), {});
  std::vector<FilterStep> filters;
  ParamValues inpaint = validate(inpaint_schema(), {});

  void add_filter(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                  const std::map<std::string, std::string>& paths = {});
  // The cloud attributes the rasterize stage reads (only those are uploaded;
  // normals a cloud lacks are estimated for it, once, when a style asks).
  uint32_t required_attributes() const;
  uint32_t color_attribute() const;  // the one of the color source (0: constant)
  bool shaded() const;
};

struct Instance {
  std::shared_ptr<const PointCloud> cloud;
  glm::dmat4 world_from_object{1.0};
};

struct Segment {
  std::string name;
  Style style;
  std::vector<Instance> instances;
};

struct Scene {
  std::vector<Segment> segments;  // order = layering order (later on top)
};

}  // namespace pointnpr
