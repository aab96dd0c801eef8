// The gaussians mark's GL backend: the per-pixel compositing as a compute
// pass (shaders/gaussians.comp, splat_alpha() of gaussians_kernels.glsl,
// the native path's own text), one 16 x 16 workgroup per tile, each pixel
// walking its tile's list in the sorted order. The splats' projection, SH
// colour, binning and sort are the native path's (native.cpp), so both
// backends composite the same records in the same order.
#include <algorithm>

#include "core/error.h"
#include "marks/gaussians/gaussians.h"

namespace pointnpr::gaussians {

void composite_gl(const MarkContext& ctx, const DrawSettings& s, const std::vector<GpuRecord>& records,
                  const std::vector<uint32_t>& start, const std::vector<uint32_t>& lists, int tiles_x, int tiles_y) {
  const Rect clip = ctx.clip;
  auto upload = [&](const void* data, size_t bytes, int index) -> const gl::Buffer& {
    const gl::Buffer& buffer = ctx.targets.scratch_buffer(std::max<size_t>(bytes, 16), index);
    if (bytes > 0) glNamedBufferSubData(buffer.id(), 0, GLsizeiptr(bytes), data);
    return buffer;
  };
  const gl::Buffer& rec = upload(records.data(), records.size() * sizeof(GpuRecord), 0);
  const gl::Buffer& starts = upload(start.data(), start.size() * sizeof(uint32_t), 1);
  const gl::Buffer& list = upload(lists.data(), lists.size() * sizeof(uint32_t), 2);
  const gl::Program& p = ctx.shaders->compute("gaussians.comp");
  p.use();
  glUniform2i(p.location("u_clip_min"), clip.min.x, clip.min.y);
  glUniform2i(p.location("u_size"), clip.size().x, clip.size().y);
  glUniform1i(p.location("u_tiles_x"), tiles_x);
  glUniform1f(p.location("u_depth_alpha"), s.depth_alpha);
  glUniform1f(p.location("u_min_coverage"), s.min_coverage);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, rec.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, starts.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, list.id());
  glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  if (tiles_x > 0 && tiles_y > 0) glDispatchCompute(GLuint(tiles_x), GLuint(tiles_y), 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

}  // namespace pointnpr::gaussians
