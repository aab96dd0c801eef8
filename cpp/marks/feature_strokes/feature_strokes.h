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

#include "core/glsl.h"
#include "core/hash.h"
#include "render/mark.h"

namespace pointnpr {

constexpr int kStrokeResolutionNeighbors = 8;  // local resolution: disc sizes and dithering
constexpr float kMaxDiscPixels = 64.0f;        // largest visibility disc (pixels)

namespace feature_strokes {
using namespace glsl;
#include "feature_strokes_settings.glsl"
static_assert(sizeof(Record) == 64, "std430 layout of Record");

// What a capture of the marks reports of a record (length in scene units).
inline CapturedMark captured(const Record& rec, bool ortho, float px_per_unit) {
  CapturedMark m;
  m.point_id = rec.point_id;
  m.center = glm::vec3(rec.center_kind);
  m.direction = glm::vec3(rec.dir_length);
  m.kind = uint32_t(rec.center_kind.w);
  m.length = rec.dir_length.w * (ortho ? 1.0f : -rec.center_kind.z) / px_per_unit;
  m.color = rec.color;
  return m;
}
}  // namespace feature_strokes

// The parameters as both backends read them, resolved once per frame: the
// kernels' settings block (shaders/feature_strokes_settings.glsl) and what
// the passes around them need.
struct FeatureStrokeSettings {
  feature_strokes::FeatureStrokesSettings u{};
  int feature_k = 8;
  AttributeKey degree_key;  // feature_degree_key: neighbours and colour weight
  AttributeKey line_key;
  ColorSource color_source = ColorSource::Constant;
  glm::vec4 paper{1.0f};
  float disc_scale = 1.5f, depth_offset = 1.5f;
  const gl::Texture* texture_image = nullptr;
  bool queue = false;
  bool lit = false;                     // shading is not none (lit_by_shading decides per chunk)
  bool opacity_draws = false;           // a stroke only where id_rand(point id) < the splat's opacity
  const ParamValues* params = nullptr;  // the frame's (lit_by_shading)
  std::vector<uint32_t> drawn;      // per chunk: points of its queue considered
  // Per chunk: points of its queue visited, drawn + those past it that only
  // draw their chain's link (all, while chains draw: a line is a line at any
  // distance; its links' ink follows its length on screen, not the queue).
  std::vector<uint32_t> visited;
  std::vector<float> inv_median_r;  // per chunk: 1 / its cloud's median local resolution
  // Per chunk: the largest local resolution a point's marks use, twice its
  // cloud's sparse spacing. A point farther from its neighbours than
  // nearly all the scan's (alone in the sky, a stray return) would get a
  // visibility disc and dithering marks the size of its gap; it gets those
  // of the scan's sparsest regular part instead.
  std::vector<float> max_r;
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
