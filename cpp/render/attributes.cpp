#include "render/attributes.h"

#include <algorithm>
#include <cmath>

namespace pointnpr {

const char* attribute_name(AttributeKind attribute) {
  switch (attribute) {
    case AttributeKind::Color: return "colors";
    case AttributeKind::Intensity: return "intensity";
    case AttributeKind::Classification: return "classification";
    case AttributeKind::AutoColor: return "auto_color";
    case AttributeKind::PointId: return "point_index";
    case AttributeKind::Normal: return "normals";
    case AttributeKind::Curvature: return "curvature";
    case AttributeKind::LocalResolution: return "local_resolution";
    case AttributeKind::FeatureDegree: return "feature_degree";
    case AttributeKind::QueueOrder: return "queue_order";
    case AttributeKind::FeatureLine: return "feature_line";
    case AttributeKind::ResolutionDeviation: return "resolution_deviation";
    case AttributeKind::PrincipalAxis: return "principal_axis";
    case AttributeKind::RadiusNormal: return "normals_3r";
    case AttributeKind::ClusterShape: return "cluster_shape";
    case AttributeKind::SplatRadius: return "splat_radius";
    case AttributeKind::SplatOpacity: return "splat_opacity";
  }
  return "?";
}

bool is_source_attribute(AttributeKind attribute) {
  switch (attribute) {
    case AttributeKind::Color:
    case AttributeKind::Intensity:
    case AttributeKind::Classification:
    case AttributeKind::AutoColor:
    case AttributeKind::PointId:
    case AttributeKind::Normal: return true;
    default: return false;
  }
}

std::vector<std::string> source_attribute_names(const AttributeSet& set) {
  std::vector<std::string> out;
  for (const AttributeKey& key : set) {
    // Normals within 3r are the cloud's own where it has them.
    const bool radius_normals = key.attribute == AttributeKind::RadiusNormal;
    if (!is_source_attribute(key.attribute) && !radius_normals) continue;
    // The host cannot know which colour a cloud it has not read yet has:
    // it passes every one of them the object has.
    const std::vector<std::string> names =
        key.attribute == AttributeKind::AutoColor ? std::vector<std::string>{"colors", "intensity", "classification"}
        : radius_normals                          ? std::vector<std::string>{"normals"}
                                                  : std::vector<std::string>{attribute_name(key.attribute)};
    for (const std::string& name : names)
      if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
  }
  return out;
}

namespace {
int twentieths(double value) { return std::clamp(int(std::floor(value * 20.0 + 1e-9)), 0, 20); }
}  // namespace

AttributeKey feature_degree_key(int feature_neighbors, double color_weight) {
  return {AttributeKind::FeatureDegree, std::clamp(feature_neighbors, 1, 99) + 100 * twentieths(color_weight)};
}

AttributeKey feature_line_key(int line_neighbors, int feature_neighbors, double threshold, double color_weight) {
  return {AttributeKind::FeatureLine, std::clamp(line_neighbors, 1, 99) + 100 * std::clamp(feature_neighbors, 1, 99) +
                                          10000 * twentieths(threshold) + 210000 * twentieths(color_weight)};
}

FeatureDegreeSpec feature_degree_spec(const AttributeKey& key) {
  if (key.attribute == AttributeKind::FeatureLine)
    return {key.k / 100 % 100, float(key.k / 210000) * 0.05f};
  return {key.k % 100, float(key.k / 100) * 0.05f};
}

FeatureLineSpec feature_line_spec(const AttributeKey& key) {
  return {key.k % 100, float(key.k / 10000 % 21) * 0.05f, feature_degree_spec(key)};
}

std::string to_string(const AttributeKey& key) {
  std::string s = attribute_name(key.attribute);
  if (key.k > 0) {
    s.push_back(':');
    s.append(std::to_string(key.k));
  }
  return s;
}

}  // namespace pointnpr
