#pragma once
// The renderer's images and buffers for one frame size (a tile's region):
// the splatting targets, the segment's colour and depth, the accumulated
// composite, the GL depth attachment, and the scratch the stages and marks
// ask for by index. Made again only when the size or the atomics change.
#include <deque>
#include <map>
#include <utility>

#include <glm/glm.hpp>

#include "gl/objects.h"
#include "render/filter.h"  // Rect

namespace pointnpr {

struct FrameTargets {
  glm::ivec2 size{0, 0};
  bool int64 = false;
  gl::Buffer depth_keys;  // uint per pixel (or uint64 per pixel with int64 atomics)
  gl::Buffer keys;        // uint per pixel (32-bit path)
  gl::Buffer bbox;        // 4 ints
  gl::Texture raster_color, raster_depth, color_a, color_b, inpainted, accum, accum_depth, accum_index, accum_added;
  gl::Texture gl_depth;   // depth attachment of GL-drawn marks
  gl::Framebuffer fbo;
  std::deque<gl::Texture> scratch;  // RGBA32F for filters; deque: references stay valid as it grows
  gl::Texture gap_filled;           // RGBA32F: the filter chain's gap fill (made on first use)
  gl::Texture gap_depth;            // R32F: its depths (made on first use)
  // R32F: each pixel's point's spacing, view units (the points mark, for the
  // gap fill), and the GL_POINTS framebuffer writing it as colour 2; made on
  // first use.
  gl::Texture raster_spacing;
  gl::Framebuffer spacing_fbo;
  std::map<std::pair<GLenum, int>, gl::Texture> mark_images;

  // Every target at `size` (with 64-bit atomics: one depth-and-key buffer).
  void ensure(glm::ivec2 size, bool int64);
  // The filters' RGBA32F scratch image `index`.
  const gl::Texture& filter_scratch(int index);
  // The filter chain's gap-filled image (shaders/gap_fill.comp).
  const gl::Texture& gap_fill_image();
  const gl::Texture& gap_depth_image();
  // raster_spacing (and spacing_fbo), made on first use.
  const gl::Texture& spacing_image();
  // A mark's scratch image of `format`, by index.
  const gl::Texture& mark_scratch(GLenum format, int index);
  // Clears whole rows [r.min.y, r.max.y) of a per-pixel buffer to ~0: one call.
  void clear_rows(const gl::Buffer& b, const Rect& r, size_t bytes_per_pixel) const;
};

// Clears rectangle r of a texture to `value`.
void clear_texture_rect(const gl::Texture& t, const Rect& r, const void* value, GLenum format, GLenum type);

// Marks' scratch buffers: by index, grown to a power of two when asked for
// more, kept across frames (they do not depend on the frame size).
class ScratchBuffers {
 public:
  const gl::Buffer& get(size_t bytes, int index);

 private:
  struct Entry {
    size_t bytes = 0;
    gl::Buffer buffer;
  };
  std::map<int, Entry> buffers_;
};

}  // namespace pointnpr
