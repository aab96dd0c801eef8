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
