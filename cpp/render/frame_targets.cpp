#include "render/frame_targets.h"

#include <string>

#include "core/error.h"
#include "gl/device.h"

namespace pointnpr {

void FrameTargets::ensure(glm::ivec2 new_size, bool new_int64) {
  if (size == new_size && int64 == new_int64) return;
  const int max_size = gl::Device::instance().info().max_texture_size;
  if (new_size.x > max_size || new_size.y > max_size)
    throw GLError("image size " + std::to_string(new_size.x) + "x" + std::to_string(new_size.y) +
                  " exceeds the GL limit of " + std::to_string(max_size));
  *this = FrameTargets();
  size = new_size;
  int64 = new_int64;
  const size_t pixels = size_t(size.x) * size_t(size.y);
  depth_keys = gl::make_buffer(pixels * (int64 ? 8 : 4), nullptr);
  keys = gl::make_buffer(int64 ? 4 : pixels * 4, nullptr);
  bbox = gl::make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
  raster_color = gl::Texture(GL_RGBA32F, size);
  raster_depth = gl::Texture(GL_R32F, size);
  color_a = gl::Texture(GL_RGBA32F, size);
  color_b = gl::Texture(GL_RGBA32F, size);
  inpainted = gl::Texture(GL_R32F, size);
  accum = gl::Texture(GL_RGBA32F, size);
  accum_depth = gl::Texture(GL_R32F, size);
  accum_index = gl::Texture(GL_R32I, size);
  accum_added = gl::Texture(GL_R32I, size);
  gl_depth = gl::Texture(GL_DEPTH_COMPONENT32F, size);
  fbo = gl::make_framebuffer({&raster_color, &raster_depth}, &gl_depth, "GL_POINTS");
  gl::check_gl("frame target allocation");
}

const gl::Texture& FrameTargets::spacing_image() {
  if (raster_spacing.id() == 0) {
    raster_spacing = gl::Texture(GL_R32F, size);
    spacing_fbo = gl::make_framebuffer({&raster_color, &raster_depth, &raster_spacing}, &gl_depth, "GL_POINTS spacing");
  }
  return raster_spacing;
}

const gl::Texture& FrameTargets::gap_depth_image() {
  if (gap_depth.id() == 0) gap_depth = gl::Texture(GL_R32F, size);
  return gap_depth;
}

const gl::Texture& FrameTargets::gap_fill_image() {
  if (gap_filled.id() == 0) gap_filled = gl::Texture(GL_RGBA32F, size);
  return gap_filled;
}

const gl::Texture& FrameTargets::filter_scratch(int index) {
  while (int(scratch.size()) <= index) scratch.emplace_back(GL_RGBA32F, size);
  return scratch[size_t(index)];
}

const gl::Texture& FrameTargets::mark_scratch(GLenum format, int index) {
  auto it = mark_images.find({format, index});
  if (it == mark_images.end())
    it = mark_images.emplace(std::make_pair(format, index), gl::Texture(format, size)).first;
  return it->second;
}

void FrameTargets::clear_rows(const gl::Buffer& b, const Rect& r, size_t bytes_per_pixel) const {
  if (r.empty()) return;
  const size_t first = size_t(r.min.y) * size_t(size.x) * bytes_per_pixel;
  const size_t count = size_t(r.size().y) * size_t(size.x) * bytes_per_pixel;
  const uint32_t ones = 0xffffffffu;
  glClearNamedBufferSubData(b.id(), GL_R32UI, GLintptr(first), GLsizeiptr(count), GL_RED_INTEGER, GL_UNSIGNED_INT,
                            &ones);
}

void clear_texture_rect(const gl::Texture& t, const Rect& r, const void* value, GLenum format, GLenum type) {
  if (r.empty()) return;
  glClearTexSubImage(t.id(), 0, r.min.x, r.min.y, 0, r.size().x, r.size().y, 1, format, type, value);
}

const gl::Buffer& ScratchBuffers::get(size_t bytes, int index) {
  Entry& b = buffers_[index];
  if (b.bytes < bytes || !b.buffer) {
    size_t grown = 256;
    while (grown < bytes) grown *= 2;
    b.buffer = gl::make_buffer(grown, nullptr, GL_DYNAMIC_STORAGE_BIT);
    b.bytes = grown;
  }
  return b.buffer;
}

}  // namespace pointnpr
