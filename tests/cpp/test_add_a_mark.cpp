// "Add a mark" (docs/architecture.md), done for a tiny example mark: one
// file holding its schema, its Mark and the one registration line, nothing
// else touched. The renderer then validates its parameters, culls, tiles
// and composites it like any other mark. (Here it lives in the test binary;
// a real one is a folder cpp/marks/<id>/, which the build globs.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/mark.h"
#include "scene/camera.h"
#include "scene/point_cloud.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

// The example: every point a square dot of `dot_size` pixels and one
// colour, nearest in front, drawn on the CPU (a GL pass would bind the
// chunk with bind_chunk() and draw a shader from shaders/ instead).
class ExampleDots : public Mark {
 public:
  AttributeSet attributes(const ParamValues&) const override { return {}; }  // positions only
  MarkExtent extent(const ParamValues& p) const override { return {0.0, 0.5f * float(p.get_float("dot_size"))}; }
  bool draws_tiles(const ParamValues&) const override { return true; }  // honours origin and frame_size

  void draw(const MarkContext& ctx, const ParamValues& p) const override {
    const Rect clip = ctx.clip;
    const glm::ivec2 size = clip.size();
    const glm::vec4 color = p.get_color("color");
    const int half = int(p.get_float("dot_size")) / 2;
    const glm::vec2 frame(frame_size(ctx.targets));
    const glm::mat4 projection(ctx.camera->projection);
    std::vector<float> rgba(size_t(size.x) * size_t(size.y) * 4, 0.0f);
    std::vector<float> depth(size_t(size.x) * size_t(size.y), std::numeric_limits<float>::infinity());
    for (const VisibleChunk& v : ctx.chunks) {
      const auto cloud = v.gpu->source.lock();
      const glm::vec3* positions = cloud->local_positions().data() + v.chunk->first;
      for (uint32_t j = 0; j < v.chunk->count; ++j) {
        const glm::vec4 view = v.view_from_chunk * glm::vec4(positions[j], 1.0f);
        const glm::vec4 c = projection * view;
        if (!(c.w > 0.0f)) continue;
        const glm::ivec2 pixel = glm::ivec2(glm::floor((glm::vec2(c) / c.w * 0.5f + 0.5f) * frame)) -
                                 ctx.targets.origin - clip.min;
        for (int y = pixel.y - half; y <= pixel.y + half; ++y)
          for (int x = pixel.x - half; x <= pixel.x + half; ++x) {
            if (x < 0 || y < 0 || x >= size.x || y >= size.y) continue;
            const size_t q = size_t(y) * size_t(size.x) + size_t(x);
            if (-view.z >= depth[q]) continue;
            depth[q] = -view.z;
            for (int ch = 0; ch < 4; ++ch) rgba[4 * q + size_t(ch)] = color[ch];
          }
      }
    }
    std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(0, size.x - 1));  // (every row: the renderer scans)
    upload_cpu_mark(ctx.targets, clip, rgba.data(), depth.data(), row_span, ctx.coverage, "example_dots");
  }
};

// The one registration line (with the schema: validation, bindings, UI
// and docs come from it).
const MarkRegistration registration{
    {Schema{"example_dots", "Example Dots", "Square dots of one colour (docs/architecture.md: add a mark).",
            {float_param("dot_size", 3.0, 1.0, 15.0, "px", "Side of a dot"),
             color_param("color", {0.9, 0.1, 0.1, 1.0}, "Dot colour")}},
     [] { return std::make_unique<ExampleDots>(); }}};

size_t covered(const RenderResult& r) {
  size_t n = 0;
  for (size_t p = 3; p < r.color.size(); p += 4) n += r.color[p] > 0.0f;
  return n;
}

RenderResult render_dots(Renderer& renderer, double dot_size, int tile_size = 0) {
  Style style;
  style.set_mark("example_dots", {{"dot_size", {dot_size}}});
  Scene scene;
  scene.segments.push_back(segment("dots", plane_cloud(-1.0, 1.0, -0.7, 0.7, -5.0, 0.1, {0, 0, 0}), style));
  RenderSettings s = settings({200, 150});
  s.tile_size = tile_size;
  return renderer.render(scene, front_camera({0, 0, 0}, {200, 150}), s);
}

TEST(AddAMark, AnExampleMarkRegisteredInOneFileDrawsAndIsValidated) {
  EXPECT_EQ(find_mark("example_dots").schema.kind, "mark");
  EXPECT_THROW(validate(find_mark("example_dots").schema, {{"dot_size", {40.0}}}), ParameterError);
  Renderer renderer;
  const RenderResult small = render_dots(renderer, 1.0), large = render_dots(renderer, 5.0);
  // 21 x 15 grid points, a dot each; bigger dots cover more.
  EXPECT_GE(covered(small), 21u * 15u - 10u);
  EXPECT_GT(covered(large), 4 * covered(small));
  // Its colour, with the frame's background elsewhere.
  size_t red = 0;
  for (size_t p = 0; p < large.color.size(); p += 4)
    red += large.color[p + 3] > 0.0f && large.color[p] > 4.0f * large.color[p + 1];
  EXPECT_EQ(red, covered(large));
  // Tiles draw the whole frame's bytes (draws_tiles).
  const RenderResult tiled = render_dots(renderer, 5.0, 64);
  ASSERT_GT(tiled.stats.at("tiles"), 1.0);
  EXPECT_EQ(tiled.color, large.color);
}

}  // namespace
