#pragma once
// Renders a Scene of segments: per segment rasterize -> filters -> depth
// inpainting -> composite (Wegen et al. 2024), on the core's GL thread.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "render/style.h"
#include "scene/camera.h"

namespace pointnpr {

class RenderCancelled : public Error {
 public:
  RenderCancelled() : Error("render cancelled") {}
};

enum class RasterizerKind { Compute, GlPoints };
RasterizerKind parse_rasterizer(const std::string& s);

struct RenderSettings {
  int width = 0;
  int height = 0;
  double time = 0.0;  // scene time in seconds (animated filters)
  ParamValues composite = validate(composite_schema(), {});
  glm::dvec4 background{0.0, 0.0, 0.0, 0.0};  // scene-linear, straight alpha
  RasterizerKind rasterizer = RasterizerKind::Compute;
  // Called between segments on the calling thread; returning false cancels.
  std::function<bool(double fraction, const std::string& what)> progress;
};

struct RenderResult {
  int width = 0;
  int height = 0;
  std::vector<float> color;           // w*h*4, scene-linear premultiplied RGBA, row 0 = bottom
  std::vector<float> depth;           // w*h, linear view depth; background = kBackgroundDepth
  std::vector<int32_t> segment_index; // w*h, front segment, -1 = background
  std::map<std::string, double> stats;
  std::vector<std::string> warnings;
};

constexpr float kBackgroundDepth = 1e10f;  // Blender's convention for empty depth

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  RenderResult render(const Scene& scene, const Camera& camera, const RenderSettings& settings);

  // Number of clouds with GPU buffers, and which attributes they hold
  // (for tests of lazy, cached uploads).
  size_t cached_clouds() const;
  uint32_t uploaded_attributes(uint64_t cloud_id) const;
  uint64_t upload_count() const;  // buffers uploaded since construction

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace pointnpr
