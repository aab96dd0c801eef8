#include "render/segment_stages.h"

#include "gl/device.h"

namespace pointnpr {

StageTimer::~StageTimer() {
  if (wait_) glFinish();
  stats_[name_] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
}

const gl::Texture& inpaint_depth_stage(gl::ShaderLibrary& shaders, const FrameTargets& targets,
                                       const ParamValues& inpaint, const gl::Texture& filtered, const Rect& rect) {
  const gl::Program& p = shaders.compute("inpaint_depth.comp");
  p.use();
  glUniform1f(p.location("u_threshold"), float(inpaint.get_float("threshold")));
  glUniform1i(p.location("u_radius"), inpaint.get_int("radius"));
  glUniform1i(p.location("u_method"), inpaint.get_enum("method"));
  glUniform1f(p.location("u_discontinuity"), float(inpaint.get_float("discontinuity")));
  glBindImageTexture(0, targets.raster_color.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, filtered.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(2, targets.raster_depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(3, targets.inpainted.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  dispatch_rect(p, rect);
  gl::check_gl("depth inpainting");
  return targets.inpainted;
}

void composite_stage(gl::ShaderLibrary& shaders, const FrameTargets& targets, CompositeMode mode, int index,
                     const gl::Texture& color, const gl::Texture& depth, const Rect& rect) {
  const gl::Program& p = shaders.compute("composite.comp");
  p.use();
  glUniform1i(p.location("u_mode"), int(mode));
  glUniform1i(p.location("u_segment"), index);
  glBindImageTexture(0, color.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(2, targets.accum.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(3, targets.accum_depth.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  glBindImageTexture(4, targets.accum_index.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32I);
  glBindImageTexture(5, targets.accum_added.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32I);
  dispatch_rect(p, rect);
  gl::check_gl("compositing");
}

}  // namespace pointnpr
