#pragma once
// The feature_strokes mark's two paths: its GL passes (marks/
// feature_strokes.cpp, which declares the schema) and the same passes on
// the CPU's threads (marks/feature_strokes/native.cpp), which `rasterizer`
// `auto` takes on software GL devices (llvmpipe), as the points mark does.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "render/mark.h"

namespace pointnpr {

constexpr int kStrokeResolutionNeighbors = 8;  // local resolution: disc sizes and dithering
constexpr float kMaxDiscPixels = 64.0f;        // largest visibility disc (pixels)

// The parameters as the passes read them, resolved once per frame.
struct FeatureStrokeSettings {
  int feature_k = 8;
  float threshold = 0.35f;
  float line_error = 0.2f;
  bool use_lines = true;
  AttributeKey line_key;
  float dither = 0.15f;
  float dither_tone = 0.5f;
  uint32_t seed = 0;
  int primitive[3] = {3, 2, 1};  // per class (directional, non-directional, dithering): 0 none, 1 sprite, 2 line, 3 textured
  float directional_length = 14.0f, other_length = 6.0f;
  float sprite_size = 3.0f, stroke_width = 4.0f, line_width = 1.2f;
  bool point_coloring = false;
  glm::vec4 stroke_color{0.0f};
  ColorSource color_source = ColorSource::Constant;
  float opacity = 0.9f;
  glm::vec4 paper{1.0f};
  float disc_scale = 1.5f, depth_offset = 1.5f;
  glm::vec2 screen_dir{1.0f, 0.0f};  // unit, pixels (x right, y up)
  int texture = 0;                   // taper, brush, dry, image
  const gl::Texture* texture_image = nullptr;
  bool queue = false;
  std::vector<uint32_t> drawn;        // per chunk: points of its queue considered
  std::vector<float> inv_median_r;    // per chunk: 1 / its cloud's median local resolution
};

// The packed line fits (AttributeKind::FeatureLine) on the host, read back
// from the GPU cloud once per cloud and key (the upload computes them; the
// fit is not cached elsewhere). One key per cloud is kept: an animated
// threshold replaces it rather than piling up copies.
class FeatureLineHostCache {
 public:
  std::shared_ptr<const std::vector<uint32_t>> get(const VisibleChunk& chunk, AttributeKey key);

 private:
  struct Entry {
    std::weak_ptr<const PointCloud> cloud;
    AttributeKey key;
    std::shared_ptr<const std::vector<uint32_t>> lines;
  };
  std::mutex mutex_;
  std::map<uint64_t, Entry> entries_;
};

// Visibility discs, selection, primitives, blending and the resolve on the
// CPU's threads (TBB), uploaded into ctx.targets.color and .depth over
// ctx.clip. Every pixel is evaluated from its frame pixel and blends its
// primitives in the GL path's primitive order, so tiles are the frame's
// bytes and no thread count or timing changes one; against the GL path it
// differs only in the last bits of the kernels (exp, pow, texture
// filtering) and in rare ties of coverage (tests/python/
// test_marks_feature_strokes.py states the tolerance).
void draw_feature_strokes_native(const MarkContext& ctx, const FeatureStrokeSettings& s,
                                 FeatureLineHostCache& lines);

}  // namespace pointnpr
