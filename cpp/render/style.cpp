#include "render/style.h"

namespace pointnpr {

const Schema& rasterize_schema() {
  static const Schema schema{
      "rasterize",
      "Rasterize",
      "Draws the segment's points as round splats into its own color and depth images.",
      {
          enum_param("size_mode", {"pixels", "world"}, 0,
                     "Point size in screen pixels, or in scene units projected by the camera"),
          float_param("point_size", 2.0, 0.5, 32.0, "px", "Splat diameter in pixels (size_mode = pixels)"),
          float_param("world_size", 0.05, 0.0001, 100.0, "m",
                      "Splat diameter in scene units (size_mode = world); capped at 32 px on screen"),
          enum_param("color_source", {"rgb", "intensity", "classification", "constant"}, 0,
                     "Where point colors come from; a cloud lacking it uses the constant color"),
          color_param("color", {0.8, 0.8, 0.8, 1.0}, "Constant color (display sRGB)"),
          enum_param("shading", {"none", "diffuse"}, 0,
                     "Light the points by their normals (the cloud's own, else estimated from neighbours, once)"),
          float_param("shading_strength", 0.7, 0.0, 1.0, "",
                      "How dark surfaces turned away from the light get (diffuse shading)"),
          float_param("light_azimuth", 135.0, -180.0, 180.0, "deg",
                      "Light direction around the view axis, from the camera (0: from the right, 90: from above)"),
          float_param("light_elevation", 45.0, 0.0, 90.0, "deg",
                      "Light direction away from the view axis (0: along it, from the camera)"),
          int_param("normal_neighbors", 16, 3, 64, "",
                    "Neighbours the normals are estimated from where a cloud has none (PCA, seed 001 eq. 1)"),
      }};
  return schema;
}

const Schema& inpaint_schema() {
  static const Schema schema{
      "inpaint",
      "Inpaint Depth",
      "Gives pixels that the filters changed a depth: the mean depth of covered pixels within a radius "
      "(Wegen et al., Listing 1).",
      {
          float_param("threshold", 0.02, 0.0, 1.0, "",
                      "Gray-level (or coverage) change above which a pixel counts as changed by the filters"),
          int_param("radius", 4, 1, 64, "px", "Radius of the circle whose covered depths are averaged"),
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

void Style::add_filter(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                       const std::map<std::string, std::string>& paths) {
  const FilterInfo& info = find_filter(id);
  FilterStep step;
  step.info = &info;
  step.params = validate(info.schema, params, paths);
  step.filter = info.create();
  filters.push_back(std::move(step));
}

uint32_t Style::color_attribute() const {
  switch (ColorSource(rasterize.get_enum("color_source"))) {
    case ColorSource::Rgb: return uint32_t(Attribute::Color);
    case ColorSource::Intensity: return uint32_t(Attribute::Intensity);
    case ColorSource::Classification: return uint32_t(Attribute::Classification);
    case ColorSource::Constant: return 0;
  }
  return 0;
}

uint32_t Style::required_attributes() const {
  return color_attribute() | (shaded() ? uint32_t(Attribute::Normal) : 0u);
}

bool Style::shaded() const { return rasterize.get_enum("shading") != 0; }

}  // namespace pointnpr
