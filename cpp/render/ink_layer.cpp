#include "render/ink_layer.h"

#include <limits>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"

namespace pointnpr {

InkLayer::InkLayer(const MarkContext& ctx, const char* what)
    : accum(ctx.targets.scratch(GL_RGBA32F, 0)),
      reveal(ctx.targets.scratch(GL_R32F, 0)),
      depth(ctx.targets.scratch(GL_R32F, 1)),
      ctx_(ctx) {
  const Rect& clip = ctx.clip;
  const float zero4[4] = {0, 0, 0, 0}, one = 1.0f, inf = std::numeric_limits<float>::infinity();
  glClearTexSubImage(accum.id(), 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1, GL_RGBA, GL_FLOAT, zero4);
  glClearTexSubImage(reveal.id(), 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1, GL_RED, GL_FLOAT, &one);
  glClearTexSubImage(depth.id(), 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1, GL_RED, GL_FLOAT, &inf);
  fbo_ = gl::make_framebuffer({&accum, &reveal, &depth}, ctx.targets.gl_depth, what);
}

void InkLayer::begin(bool depth_test, const ExactRaster& raster) const {
  const Rect& clip = ctx_.clip;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  raster.apply();
  set_mark_clip(clip);
  if (depth_test) {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GEQUAL);  // reversed Z
  }
  glDepthMask(GL_FALSE);
  blend_modes();
}

void InkLayer::blend_modes() {
  glEnable(GL_BLEND);
  glBlendEquationi(0, GL_FUNC_ADD);   // colour weighted by alpha: a sum
  glBlendFunci(0, GL_ONE, GL_ONE);
  glBlendEquationi(1, GL_FUNC_ADD);   // transmittance: a product
  glBlendFunci(1, GL_ZERO, GL_ONE_MINUS_SRC_COLOR);
  glBlendEquationi(2, GL_MIN);        // nearest depth
  glBlendFunci(2, GL_ONE, GL_ONE);
}

void InkLayer::end() const { restore_raster_defaults(); }

void InkLayer::resolve(glm::vec4 paper, bool surface) const {
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  const gl::Program& p = ctx_.shaders->compute("ink_resolve.comp");
  p.use();
  glUniform4fv(p.location("u_paper"), 1, glm::value_ptr(paper));
  glUniform1i(p.location("u_surface"), surface ? 1 : 0);
  glBindImageTexture(0, ctx_.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx_.targets.depth->id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  glBindImageTexture(2, accum.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(3, reveal.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(4, depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  dispatch_rect(p, ctx_.clip);
}

void draw_record_batch(const gl::Buffer& commands, const RecordBatch& batch) {
  if (batch.draws() == 0) return;
  GLuint vao = 0;
  glCreateVertexArrays(1, &vao);
  const gl::VertexArray empty_vao(vao);
  glBindVertexArray(vao);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands.id());
  glMultiDrawArraysIndirect(GL_TRIANGLES, nullptr, batch.draws(), 0);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glBindVertexArray(0);
}

}  // namespace pointnpr
