#pragma once
// The stages of a segment after its mark (Renderer's render_segment reads as
// mark -> filters -> inpaint -> composite): each names the frame targets it
// reads and writes, and is timed by a StageTimer.
#include <chrono>
#include <map>
#include <string>

#include "core/params.h"
#include "gl/objects.h"
#include "gl/shaders.h"
#include "render/filter.h"
#include "render/frame_targets.h"
#include "render/style.h"

namespace pointnpr {

// Adds a stage's milliseconds to stats[name] when it ends. With `wait`
// (RenderSettings::stage_timings) the stage's GPU work is waited for first,
// so that its time holds it; never in production (a stall a stage).
class StageTimer {
 public:
  StageTimer(std::map<std::string, double>& stats, const char* name, bool wait)
      : stats_(stats), name_(name), wait_(wait), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  std::map<std::string, double>& stats_;
  const char* name_;
  bool wait_;
  std::chrono::steady_clock::time_point start_;
};

// Depth inpainting (seed 000's occlusion fix): reads targets.raster_color,
// `filtered` and targets.raster_depth over `rect`; writes targets.inpainted,
// which it returns for compositing.
const gl::Texture& inpaint_depth_stage(gl::ShaderLibrary& shaders, const FrameTargets& targets,
                                       const ParamValues& inpaint, const gl::Texture& filtered, const Rect& rect);

// Compositing: `color` and `depth` of segment `index` over `rect` into the
// frame's accumulation (targets.accum, accum_depth, accum_index,
// accum_added) by `mode`.
void composite_stage(gl::ShaderLibrary& shaders, const FrameTargets& targets, CompositeMode mode, int index,
                     const gl::Texture& color, const gl::Texture& depth, const Rect& rect);

}  // namespace pointnpr
