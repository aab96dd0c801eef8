#pragma once
// Runs filters on a synthetic image through the Renderer's filter chain
// (cpp/render/filter_chain.cpp): the rect starts at the covered bounds and grows
// by each filter's footprint, filters ping-pong two RGBA32F images, get the
// raster depth and scratch images. Used by tests/cpp/test_filters*.cpp and
// bench/bench_filters.cpp; the Renderer itself is exercised by the
// Filter*ThroughTheRenderer tests.
//
// To catch filters that write outside their rect or rely on undefined
// scratch contents, the output image starts as a sentinel colour (single
// filter runs) and scratch images start as NaN.
#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <cmath>
#include <cstdint>
#include <deque>
#include <glm/glm.hpp>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gl/device.h"
#include "gl/objects.h"
#include "gl/shaders.h"
#include "render/filter_chain.h"

namespace pointnpr::test {

// Straight-alpha RGBA float image, row 0 = bottom, plus linear depth.
struct Image {
  glm::ivec2 size{0, 0};
  std::vector<float> rgba;   // 4 per pixel
  std::vector<float> depth;  // 1 per pixel; +inf = empty (filled from alpha when left empty)
  // The scan's spacing handed to the chain (ScanSampling::spacing; the
  // harness's view is one unit per pixel); 0 = unknown.
  float spacing = 0.0f;
  // Each pixel's point's spacing (FilterChainImages::raster_spacing), or
  // empty: none handed over.
  std::vector<float> pixel_spacing;

  Image() = default;
  explicit Image(glm::ivec2 s) : size(s), rgba(size_t(s.x) * size_t(s.y) * 4, 0.0f) {}
  size_t index(int x, int y) const { return size_t(y) * size_t(size.x) + size_t(x); }
  glm::vec4 at(int x, int y) const {
    const float* c = &rgba[4 * index(x, y)];
    return {c[0], c[1], c[2], c[3]};
  }
  void set(int x, int y, glm::vec4 c) {
    float* d = &rgba[4 * index(x, y)];
    d[0] = c.r, d[1] = c.g, d[2] = c.b, d[3] = c.a;
  }
};

inline const glm::vec4 kSentinel(0.123f, 0.456f, 0.789f, 0.321f);

struct Step {
  std::string id;
  std::map<std::string, std::vector<double>> params;
  std::map<std::string, std::string> paths;  // image parameters
};

struct FilterRun {
  Image out;
  Rect rect;          // the last filter's rect
  double gpu_ms = 0;  // filters only, glFinish'ed
};

inline Rect covered_bounds(const Image& img) {
  Rect r{{img.size.x, img.size.y}, {0, 0}};
  for (int y = 0; y < img.size.y; ++y)
    for (int x = 0; x < img.size.x; ++x)
      if (img.at(x, y).a > 0.0f) {
        r.min = glm::min(r.min, glm::ivec2(x, y));
        r.max = glm::max(r.max, glm::ivec2(x + 1, y + 1));
      }
  return r.empty() ? Rect{} : r;
}

// Runs `steps` on `in`; `repeat` > 1 runs the chain that many times (for
// benchmarks) and reports the mean time.
// `fill_gaps`: the chain's gap fill before neighbourhood filters (off:
// the filters alone, for cost comparisons).
inline FilterRun run_filters(const Image& in, const std::vector<Step>& steps, double time = 0.0, int repeat = 1,
                             std::optional<Rect> start_rect = std::nullopt, bool fill_gaps = true) {
  std::vector<FilterStep> chain;
  for (const Step& s : steps) chain.push_back(make_filter_step(s.id, s.params, s.paths));
  std::vector<float> depth = in.depth;
  if (depth.empty()) {
    depth.resize(size_t(in.size.x) * size_t(in.size.y));
    for (size_t i = 0; i < depth.size(); ++i)
      depth[i] = in.rgba[4 * i + 3] > 0.0f ? 10.0f : std::numeric_limits<float>::infinity();
  }
  return gl::Device::instance().run([&] {
    static gl::ShaderLibrary* shaders = new gl::ShaderLibrary();  // lives as long as the GL context
    const glm::ivec2 size = in.size;
    gl::Texture a(GL_RGBA32F, size), b(GL_RGBA32F, size), z(GL_R32F, size), gap(GL_RGBA32F, size),
        spacing(GL_R32F, size), gap_depth(GL_R32F, size);
    if (!in.pixel_spacing.empty())
      glTextureSubImage2D(spacing.id(), 0, 0, 0, size.x, size.y, GL_RED, GL_FLOAT, in.pixel_spacing.data());
    std::deque<gl::Texture> scratch;
    const float nan4[4] = {std::nanf(""), std::nanf(""), std::nanf(""), std::nanf("")};
    glTextureSubImage2D(a.id(), 0, 0, 0, size.x, size.y, GL_RGBA, GL_FLOAT, in.rgba.data());
    glTextureSubImage2D(z.id(), 0, 0, 0, size.x, size.y, GL_RED, GL_FLOAT, depth.data());
    const bool single = chain.size() == 1;
    const float zero4[4] = {0, 0, 0, 0};
    const float sentinel[4] = {kSentinel.r, kSentinel.g, kSentinel.b, kSentinel.a};
    FilterRun run;
    double total_ms = 0.0;
    for (int rep = 0; rep < std::max(repeat, 1); ++rep) {
      glClearTexImage(b.id(), 0, GL_RGBA, GL_FLOAT, single ? sentinel : zero4);
      for (auto& t : scratch) glClearTexImage(t.id(), 0, GL_RGBA, GL_FLOAT, nan4);
      glClearTexImage(gap.id(), 0, GL_RGBA, GL_FLOAT, nan4);  // as scratch: pixels the gap fill leaves are NaN
      glFinish();
      const auto t0 = std::chrono::steady_clock::now();
      Rect rect = start_rect ? *start_rect : covered_bounds(in);
      FilterChainImages images;
      images.shaders = shaders;
      images.images = &standalone_image_textures();
      images.first = &a;
      images.second = &b;
      images.raster_depth = &z;
      images.raster_spacing = in.pixel_spacing.empty() ? nullptr : &spacing;
      images.scratch = [&](int i) -> const gl::Texture& {
        while (int(scratch.size()) <= i) {
          scratch.emplace_back(GL_RGBA32F, size);
          glClearTexImage(scratch.back().id(), 0, GL_RGBA, GL_FLOAT, nan4);
        }
        return scratch[size_t(i)];
      };
      images.image_size = size;
      images.time = time;
      images.segment_seed = 12345u;
      images.fill_gaps = fill_gaps;
      images.gap_image = [&]() -> const gl::Texture& { return gap; };
      images.gap_depth_image = [&]() -> const gl::Texture& { return gap_depth; };
      // An orthographic view one world unit per pixel: the surface point
      // of pixel q at depth d is (q, -d).
      images.surface.x0 = {1.0f, 0.0f, 0.0f};
      images.surface.y0 = {0.0f, 1.0f, 0.0f};
      images.sampling.spacing = in.spacing;
      images.sampling.depth_min = *std::min_element(depth.begin(), depth.end());
      const gl::Texture* current = run_filter_chain(chain, images, rect);
      glFinish();
      total_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      run.rect = rect;
      if (rep + 1 == std::max(repeat, 1)) {
        run.out = Image(size);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glGetTextureImage(current->id(), 0, GL_RGBA, GL_FLOAT, GLsizei(run.out.rgba.size() * 4), run.out.rgba.data());
        gl::check_gl("filter harness read back");
      }
      // The chain's input must stay the same for the next repetition.
      if (current == &a && rep + 1 < repeat)
        glTextureSubImage2D(a.id(), 0, 0, 0, size.x, size.y, GL_RGBA, GL_FLOAT, in.rgba.data());
    }
    run.gpu_ms = total_ms / double(std::max(repeat, 1));
    return run;
  });
}

inline FilterRun run_filter(const Image& in, const std::string& id,
                            std::map<std::string, std::vector<double>> params = {}) {
  return run_filters(in, {{id, std::move(params)}});
}

// Deterministic noise in [-1, 1] from pixel coordinates.
inline float hash_noise(int x, int y, uint32_t seed = 0) {
  uint32_t h = uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ (seed * 83492791u + 0x9e3779b9u);
  h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15, h *= 0x846ca68bu, h ^= h >> 16;
  return float(h & 0xffffff) / float(0xffffff) * 2.0f - 1.0f;
}

}  // namespace pointnpr::test
