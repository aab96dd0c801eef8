#include "render/native_ink.h"

#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gl/device.h"
#include "gl/objects.h"

namespace pointnpr {

bool exact_quad(const glm::vec2 (&corners)[4], glm::ivec2 origin, const Rect& clip, ExactQuad& quad) {
  int64_t min_x = INT64_MAX, min_y = INT64_MAX, max_x = INT64_MIN, max_y = INT64_MIN;
  for (int k = 0; k < 4; ++k) {
    quad.qx[k] = int32_t(round_even(corners[k].x * 256.0f));
    quad.qy[k] = int32_t(round_even(corners[k].y * 256.0f));
    min_x = std::min<int64_t>(min_x, quad.qx[k]);
    max_x = std::max<int64_t>(max_x, quad.qx[k]);
    min_y = std::min<int64_t>(min_y, quad.qy[k]);
    max_y = std::max<int64_t>(max_y, quad.qy[k]);
  }
  // Pixels whose centre (256 x + 128) can lie within the corners' box.
  auto first_pixel = [](int64_t q) { return int(((q - 128) + 255 + (int64_t(1) << 40)) / 256 - (int64_t(1) << 32)); };
  auto last_pixel = [](int64_t q) { return int(((q - 128) + (int64_t(1) << 40)) / 256 - (int64_t(1) << 32)); };
  quad.lo = glm::max(glm::ivec2(first_pixel(min_x), first_pixel(min_y)) - origin, clip.min);
  quad.hi = glm::min(glm::ivec2(last_pixel(max_x), last_pixel(max_y)) - origin + 1, clip.max);
  return quad.lo.x < quad.hi.x && quad.lo.y < quad.hi.y;
}

// Edges a -> b counter-clockwise (y up). On an edge (E == 0) a pixel centre
// belongs to left edges and bottom ones (llvmpipe's fill convention for its
// framebuffers), so two triangles sharing an edge cover each pixel once.
EdgeTriangle edge_triangle(const ExactQuad& q, int i, int j, int k) {
  int64_t x[3] = {q.qx[i], q.qx[j], q.qx[k]}, y[3] = {q.qy[i], q.qy[j], q.qy[k]};
  const int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
  EdgeTriangle t;
  if (area == 0) return t;
  if (area < 0) {
    std::swap(x[1], x[2]);
    std::swap(y[1], y[2]);
  }
  for (int n = 0; n < 3; ++n) {
    const int m = (n + 1) % 3;
    const int64_t dx = x[m] - x[n], dy = y[m] - y[n];
    t.a[n] = -dy;
    t.b[n] = dx;
    t.c[n] = -(t.a[n] * x[n] + t.b[n] * y[n]);
    if (dy < 0 || (dy == 0 && dx > 0)) t.c[n] += 1;  // E >= 0 counts (integer values)
  }
  t.empty = false;
  return t;
}

namespace {
int64_t floor_div(int64_t n, int64_t d) {  // d > 0
  const int64_t q = n / d;
  return q - ((n % d != 0) && (n < 0));
}
}  // namespace

void triangle_span(const EdgeTriangle& t, int64_t y, int64_t& first, int64_t& last) {
  const int64_t sy = y * 256 + 128;
  for (int n = 0; n < 3; ++n) {
    // a (256 x + 128) + b sy + c > 0
    const int64_t A = 256 * t.a[n], K = 128 * t.a[n] + t.b[n] * sy + t.c[n];
    if (A > 0) {
      first = std::max(first, floor_div(-K, A) + 1);
    } else if (A < 0) {
      last = std::min(last, -floor_div(-K, -A) - 1);
    } else if (K <= 0) {
      last = first - 1;
      return;
    }
  }
}

HostInk HostInkImages::clear(const Rect& clip) {
  const glm::ivec2 size = clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  if (reveal.size() < pixels) {
    accum.resize(4 * pixels);
    reveal.resize(pixels);
    depth.resize(pixels);
  }
  float* a = accum.data();
  float* r = reveal.data();
  float* d = depth.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 16), [&](const tbb::blocked_range<size_t>& b) {
    std::fill(a + 4 * b.begin(), a + 4 * b.end(), 0.0f);
    std::fill(r + b.begin(), r + b.end(), 1.0f);
    std::fill(d + b.begin(), d + b.end(), std::numeric_limits<float>::infinity());
  });
  return HostInk{a, r, d, size.x, clip.min};
}

HostTexture::HostTexture(const gl::Texture& texture, const char* what)
    : width(texture.size().x), height(texture.size().y) {
  rgba.resize(4 * size_t(width) * size_t(height));
  glGetTextureImage(texture.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)), rgba.data());
  gl::check_gl((std::string(what) + ": reading a texture back").c_str());
}

}  // namespace pointnpr
