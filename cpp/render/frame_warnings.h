#pragma once
// What a frame has to say about its input (RenderResult::warnings), each
// cause said once with counts and the first few names (500 uncoloured
// objects make one line).
#include <map>
#include <string>
#include <vector>

#include "render/attributes.h"
#include "render/gpu_cloud.h"
#include "render/style.h"

namespace pointnpr {

// The colour attribute a mark asked for by name, when the cloud lacks it
// ("" otherwise; colour source auto takes what there is, constant included).
std::string missing_color(const AttributeSet& needed, const GpuCloud& g);

// Thousands separated: "1,204,511".
std::string with_commas(size_t v);

struct FrameWarnings {
  static constexpr size_t kNamed = 3;
  std::map<std::string, std::vector<std::string>> missing_color;  // asked -> objects
  std::vector<std::string> nonfinite;                              // one line per object

  void add_missing_color(const std::string& asked, const Instance& inst, const Segment& seg);
  void add_nonfinite(const Instance& inst, const Segment& seg);
  void report(std::vector<std::string>& out) const;
};

}  // namespace pointnpr
