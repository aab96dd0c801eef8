#pragma once
// InkLayer (render/ink_layer.h) on the CPU's threads, for the native
// backends of marks drawn as GL quads (feature strokes, hatching): quads
// with corners on the 1/256 pixel grid of render/exact_raster.h, covered
// pixel by pixel as llvmpipe fills them, and the three ink images blended
// in primitive order (colour weighted by alpha: a sum; transmittance: a
// product; the nearest depth: a minimum).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "render/filter.h"
#include "render/host_scratch.h"
#include "render/native_raster.h"

namespace pointnpr::gl {
class Texture;
}

namespace pointnpr {

// A quad's corners in frame pixels x 256 (exact_window.glsl), in the GL
// order (0,0) (1,0) (1,1) (0,1), drawn as the triangles 0-1-2 and 0-2-3;
// and the tile pixels [lo, hi) whose centres it may cover.
struct ExactQuad {
  int32_t qx[4] = {}, qy[4] = {};
  glm::ivec2 lo{0}, hi{0};
};
// The quad at these frame-pixel corners; false where it covers no pixel
// of `clip` (tile pixels; the tile's frame pixel (0, 0) is `origin`).
bool exact_quad(const glm::vec2 (&corners)[4], glm::ivec2 origin, const Rect& clip, ExactQuad& quad);

// A triangle's edge functions on the 1/256 grid: E = a X + b Y + c > 0
// inside, integers, so exact.
struct EdgeTriangle {
  int64_t a[3] = {}, b[3] = {}, c[3] = {};
  bool empty = true;
};
EdgeTriangle edge_triangle(const ExactQuad& q, int i, int j, int k);
// Narrows [first, last] (frame pixels) to the pixels of frame row y whose
// centres the triangle covers.
void triangle_span(const EdgeTriangle& t, int64_t y, int64_t& first, int64_t& last);

// Calls pixel(x, y) (tile pixels) for every pixel of `area` the quad
// covers, row by row; a pixel on the diagonal both triangles share is
// covered once (each triangle's own, as the GL's fill convention).
template <class Pixel>
void for_each_covered_pixel(const ExactQuad& q, const Rect& area, glm::ivec2 origin, Pixel&& pixel) {
  const glm::ivec2 lo = glm::max(q.lo, area.min), hi = glm::min(q.hi, area.max);
  if (lo.x >= hi.x || lo.y >= hi.y) return;
  const EdgeTriangle triangles[2] = {edge_triangle(q, 0, 1, 2), edge_triangle(q, 0, 2, 3)};
  for (int y = lo.y; y < hi.y; ++y)
    for (const EdgeTriangle& t : triangles) {
      if (t.empty) continue;
      int64_t first = int64_t(lo.x) + origin.x, last = int64_t(hi.x) - 1 + origin.x;
      triangle_span(t, int64_t(y) + origin.y, first, last);
      for (int x = int(first - origin.x); x <= int(last - origin.x); ++x) pixel(x, y);
    }
}

// The ink images over a clip (tile pixels, row-major from `min`).
struct HostInk {
  float* accum;   // rgb * a, a (sums)
  float* reveal;  // transmittance (a product)
  float* depth;   // nearest linear depth
  int stride;
  glm::ivec2 min;
  size_t at(int x, int y) const { return size_t(y - min.y) * size_t(stride) + size_t(x - min.x); }
  void blend(size_t q, glm::vec3 rgb, float a, float d) const {
    float* acc = accum + 4 * q;
    acc[0] += rgb.r * a;
    acc[1] += rgb.g * a;
    acc[2] += rgb.b * a;
    acc[3] += a;
    reveal[q] *= 1.0f - a;
    depth[q] = std::min(depth[q], d);
  }
};

// Ink over paper (ink_resolve.comp), in place: accum becomes the colour
// (straight alpha), depth the segment's depth (the surface's where there is
// one, else the ink's; +inf where nothing is). `surface` is copied per
// block of rows and called as surface(q) for pixel q: the depth pass's
// linear depth there, +inf where none. Returns each row's covered columns
// [first, last] (upload_cpu_mark's row spans).
template <class Surface>
std::vector<glm::ivec2> resolve_ink(const HostInk& ink, glm::ivec2 size, glm::vec4 paper, const Surface& surface) {
  std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    Surface surface_at = surface;
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < size.x; ++x) {
        const size_t q = size_t(y) * size_t(size.x) + size_t(x);
        const float depth = surface_at(q);
        const bool on_surface = !std::isinf(depth);
        const float ink_a = 1.0f - std::clamp(ink.reveal[q], 0.0f, 1.0f);
        float* acc = ink.accum + 4 * q;
        const glm::vec3 ink_rgb = acc[3] > 0.0f ? glm::vec3(acc[0], acc[1], acc[2]) / acc[3] : glm::vec3(0.0f);
        const float under = on_surface ? paper.a : 0.0f;
        const float alpha = ink_a + under * (1.0f - ink_a);
        const glm::vec3 premultiplied = ink_rgb * ink_a + glm::vec3(paper) * under * (1.0f - ink_a);
        if (alpha > 0.0f) {
          const glm::vec3 straight = glm::clamp(premultiplied / alpha, 0.0f, 1.0f);
          acc[0] = straight.r;
          acc[1] = straight.g;
          acc[2] = straight.b;
          acc[3] = alpha;
          if (on_surface) ink.depth[q] = depth;
          row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, x), x};
        } else {
          std::fill(acc, acc + 4, 0.0f);
          ink.depth[q] = std::numeric_limits<float>::infinity();
        }
      }
  });
  return row_span;
}

// Host ink images kept by the renderer (HostScratch) from frame to frame.
struct HostInkImages {
  std::vector<float> accum, reveal, depth;
  size_t bytes() const { return held_bytes(accum) + held_bytes(reveal) + held_bytes(depth); }
  // Cleared images for `clip` (no ink: 0, transmittance 1, depth +inf).
  HostInk clear(const Rect& clip);
};

// A texture read back to the host, sampled as GL_LINEAR, CLAMP_TO_EDGE
// samples it (a stroke texture, an X-Toon image).
struct HostTexture {
  std::vector<float> rgba;
  int width = 0, height = 0;
  HostTexture() = default;
  HostTexture(const gl::Texture& texture, const char* what);
  glm::vec4 texel(int x, int y) const {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    const float* t = &rgba[4 * (size_t(y) * size_t(width) + size_t(x))];
    return {t[0], t[1], t[2], t[3]};
  }
  glm::vec4 sample(float u, float v) const {
    const float fx = u * float(width) - 0.5f, fy = v * float(height) - 0.5f;
    const float x0 = std::floor(fx), y0 = std::floor(fy);
    const float tx = fx - x0, ty = fy - y0;
    const int ix = int(std::clamp(x0, -2.0f, float(width))), iy = int(std::clamp(y0, -2.0f, float(height)));
    const glm::vec4 a = glm::mix(texel(ix, iy), texel(ix + 1, iy), tx);
    const glm::vec4 b = glm::mix(texel(ix, iy + 1), texel(ix + 1, iy + 1), tx);
    return glm::mix(a, b, ty);
  }
};

}  // namespace pointnpr
