#pragma once
// Renders a Scene of segments: per segment cull -> mark -> filters -> depth
// inpainting -> composite (Wegen et al. 2024), on the core's GL thread.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "render/native_limits.h"
#include "render/style.h"
#include "scene/camera.h"

namespace pointnpr {

class RenderCancelled : public Cancelled {
 public:
  RenderCancelled() : Cancelled("render cancelled") {}
};

// The largest frame side (frames larger than the GL's image limit are drawn in tiles).
constexpr int kMaxFrameSide = 32768;

struct RenderSettings {
  int width = 0;
  int height = 0;
  double time = 0.0;  // scene time in seconds (animated filters)
  ParamValues composite = validate(composite_schema(), {});
  glm::dvec4 background{0.0, 0.0, 0.0, 0.0};  // scene-linear, straight alpha
  // Hand back every mark drawn (RenderResult::marks), for tests and debugging.
  bool capture_marks = false;
  // GL memory the frame may take (render/tiling.h): larger frames are drawn
  // in tiles, the same bytes as drawn whole. 0 = the default (2 GiB).
  size_t memory_budget = 0;
  // Tiles of this many pixels per side whatever the budget (tests, benchmarks); 0 = from the budget.
  int tile_size = 0;
  // Most points the frame's marks draw (render/point_budget.h: each visible
  // chunk a prefix of its resolution queue, one density on screen); 0 = all.
  uint64_t point_budget = 0;
  // The native mark backends' limits (render/native_limits.h; tests lower them).
  NativeLimits native;
  // 64-bit atomics where the GL device has them (one depth-and-index key a
  // pixel); false takes the 32-bit two-pass path on any device (tests, GPU checks).
  bool int64_atomics = true;
  // Stage times that include the GPU's work: the renderer waits for the GPU
  // (glFinish) after each stage (benchmarks). Off, nothing stalls the GPU
  // between stages and a stage's time is what it took on the CPU.
  bool stage_timings = false;
  // Called between segments and tiles on the calling thread; returning false cancels.
  std::function<bool(double fraction, const std::string& what)> progress;
};

// Frame-sized buffers handed back by finished results, so the next frame
// writes into memory that is already mapped (fresh 30+ MB allocations are
// mmapped and page-faulted anew every frame otherwise).
class BufferPool {
 public:
  std::vector<float> take_floats(size_t size);
  std::vector<int32_t> take_ints(size_t size);
  void give(std::vector<float>&& v);
  void give(std::vector<int32_t>&& v);

 private:
  std::mutex mutex_;
  std::vector<std::vector<float>> floats_;
  std::vector<std::vector<int32_t>> ints_;
};

struct RenderResult {
  RenderResult() = default;
  RenderResult(RenderResult&&) = default;
  RenderResult& operator=(RenderResult&&) = default;
  ~RenderResult();  // returns the pixel buffers to the renderer's pool

  int width = 0;
  int height = 0;
  std::vector<float> color;           // w*h*4, scene-linear premultiplied RGBA, row 0 = bottom
  std::vector<float> depth;           // w*h, linear view depth; background = kBackgroundDepth
  std::vector<int32_t> segment_index; // w*h, front segment, -1 = background
  std::vector<CapturedMark> marks;    // with RenderSettings::capture_marks
  std::map<std::string, double> stats;
  std::vector<std::string> warnings;
  std::shared_ptr<BufferPool> pool;
};

constexpr float kBackgroundDepth = 1e10f;  // Blender's convention for empty depth

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Thread-safe: Blender renders F12 on its render thread while the main
  // thread may draw the viewport with the same renderer; frames are
  // serialized (the GL thread is one anyway).
  RenderResult render(const Scene& scene, const Camera& camera, const RenderSettings& settings);

  // Number of clouds with GPU buffers, and which attributes they hold
  // (for tests of lazy, cached uploads).
  size_t cached_clouds() const;
  AttributeSet uploaded_attributes(uint64_t cloud_id) const;
  uint64_t upload_count() const;  // buffers uploaded since construction
  // The same for triangle meshes (buffers and textures; render/gpu_mesh.h).
  size_t cached_meshes() const;
  uint64_t mesh_upload_count() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::mutex render_mutex_;
};

}  // namespace pointnpr
