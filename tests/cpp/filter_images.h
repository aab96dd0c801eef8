#pragma once
// Synthetic test images for the filter tests and benchmarks.
#include <cmath>

#include "filter_harness.h"

namespace pointnpr::test {

inline glm::vec3 clamp01(glm::vec3 c) { return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f)); }

// Covered rectangle [margin, size - margin) with a vertical step edge in the
// middle (`left` | `right`) plus white noise of amplitude `noise`.
inline Image step_image(glm::ivec2 size, glm::vec3 left, glm::vec3 right, float noise, int margin = 8) {
  Image img(size);
  for (int y = margin; y < size.y - margin; ++y)
    for (int x = margin; x < size.x - margin; ++x) {
      const glm::vec3 base = x < size.x / 2 ? left : right;
      const glm::vec3 n(hash_noise(x, y, 1), hash_noise(x, y, 2), hash_noise(x, y, 3));
      img.set(x, y, glm::vec4(clamp01(base + noise * n), 1.0f));
    }
  return img;
}

// A filled disk of one colour (plus optional noise) on background.
inline Image disk_image(glm::ivec2 size, glm::vec2 center, float radius, glm::vec3 color, float noise = 0.0f) {
  Image img(size);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      const glm::vec2 d = glm::vec2(x, y) + 0.5f - center;
      if (glm::dot(d, d) > radius * radius) continue;
      const glm::vec3 n(hash_noise(x, y, 4), hash_noise(x, y, 5), hash_noise(x, y, 6));
      img.set(x, y, glm::vec4(clamp01(color + noise * n), 1.0f));
    }
  return img;
}

// Smooth colourful gradients with some noise over the whole covered area.
inline Image gradient_image(glm::ivec2 size, int margin = 4) {
  Image img(size);
  for (int y = margin; y < size.y - margin; ++y)
    for (int x = margin; x < size.x - margin; ++x) {
      const float u = float(x) / float(size.x), v = float(y) / float(size.y);
      const glm::vec3 c(u, v, 0.5f + 0.5f * std::sin(6.0f * u + 4.0f * v));
      img.set(x, y, glm::vec4(clamp01(c + 0.03f * hash_noise(x, y, 7)), 1.0f));
    }
  return img;
}

// Lone points every `spacing` pixels: a sparse cloud.
inline Image sparse_points(glm::ivec2 size, int spacing, glm::vec3 color) {
  Image img(size);
  for (int y = spacing; y < size.y - spacing; y += spacing)
    for (int x = spacing; x < size.x - spacing; x += spacing) img.set(x, y, glm::vec4(color, 1.0f));
  return img;
}

}  // namespace pointnpr::test

#include <cstdio>
#include <cstdlib>
#include <string>

namespace pointnpr::test {

// With POINTNPR_FILTER_DUMP=<dir>, writes `img` over a grey checker as
// <dir>/<name>.ppm (for looking at what a test saw); otherwise does nothing.
inline void maybe_dump(const Image& img, const std::string& name) {
  const char* dir = std::getenv("POINTNPR_FILTER_DUMP");
  if (!dir) return;
  FILE* f = std::fopen((std::string(dir) + "/" + name + ".ppm").c_str(), "wb");
  if (!f) return;
  std::fprintf(f, "P6\n%d %d\n255\n", img.size.x, img.size.y);
  for (int y = img.size.y - 1; y >= 0; --y)
    for (int x = 0; x < img.size.x; ++x) {
      const glm::vec4 c = img.at(x, y);
      const float bg = ((x / 8 + y / 8) % 2) ? 0.6f : 0.4f;
      const float a = c == kSentinel ? 0.0f : glm::clamp(c.a, 0.0f, 1.0f);
      for (int k = 0; k < 3; ++k) {
        const float v = glm::clamp(c[k], 0.0f, 1.0f) * a + bg * (1.0f - a);
        std::fputc(int(std::lround(v * 255.0f)), f);
      }
    }
  std::fclose(f);
}

// Variance of the green channel over [x0,x1) x [y0,y1): noise left in a flat patch.
inline double patch_variance(const Image& img, int x0, int y0, int x1, int y1) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const double v = img.at(x, y).g;
      sum += v, sum2 += v * v, ++n;
    }
  return sum2 / n - (sum / n) * (sum / n);
}

}  // namespace pointnpr::test
