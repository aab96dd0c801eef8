#include "render/frame_warnings.h"

#include <algorithm>

#include "scene/point_cloud.h"

namespace pointnpr {

std::string missing_color(const AttributeSet& needed, const GpuCloud& g) {
  for (AttributeKind a : {AttributeKind::Color, AttributeKind::Intensity, AttributeKind::Classification})
    if (needed.count({a}) && !g.find({a})) return attribute_name(a);
  return "";
}

std::string with_commas(size_t v) {
  std::string digits = std::to_string(v), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out.push_back(',');
    out.push_back(digits[i]);
  }
  return out;
}

namespace {
std::string object_name(const Instance& inst, const Segment& seg) {
  return inst.name.empty() ? "a cloud of segment '" + seg.name + "'" : "'" + inst.name + "'";
}
std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < std::min(names.size(), FrameWarnings::kNamed); ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > FrameWarnings::kNamed) out += " and " + with_commas(names.size() - FrameWarnings::kNamed) + " more";
  return out;
}
}  // namespace

void FrameWarnings::add_missing_color(const std::string& asked, const Instance& inst, const Segment& seg) {
  missing_color[asked].push_back(object_name(inst, seg));
}

void FrameWarnings::add_nonfinite(const Instance& inst, const Segment& seg) {
  const PointCloud& c = *inst.cloud;
  const size_t total = c.size() + c.skipped_nonfinite();
  nonfinite.push_back((inst.name.empty() ? "a cloud of segment '" + seg.name + "'" : "object '" + inst.name + "'") +
                      ": " + with_commas(c.skipped_nonfinite()) + " of " + with_commas(total) +
                      " points have non-finite coordinates and were skipped");
}

void FrameWarnings::report(std::vector<std::string>& out) const {
  for (const auto& [asked, names] : missing_color)
    out.push_back(with_commas(names.size()) + (names.size() == 1 ? " object has" : " objects have") + " no " + asked +
                  (names.size() == 1 ? " for its" : " for their") + " style's colour source (" + listed(names) +
                  "); drawn in the constant colour");
  for (size_t i = 0; i < std::min(nonfinite.size(), kNamed); ++i) out.push_back(nonfinite[i]);
  if (nonfinite.size() > kNamed)
    out.push_back("and " + with_commas(nonfinite.size() - kNamed) +
                  " more objects have points with non-finite coordinates (skipped)");
}

}  // namespace pointnpr
