// Properties every filter must have, checked for all registered filters:
// deterministic, writes only its grown rect, no rings around lone points;
// then through the real Renderer. Filter-specific properties live in
// test_filters_<name>.cpp.
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "filter_images.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

std::vector<std::string> filter_ids() {
  std::vector<std::string> ids;
  for (const FilterInfo* f : registered_filters()) ids.push_back(f->schema.id);
  return ids;
}

int covered_count(const Image& img) {
  int n = 0;
  for (int y = 0; y < img.size.y; ++y)
    for (int x = 0; x < img.size.x; ++x) n += img.at(x, y).a > 0.0f && img.at(x, y) != kSentinel ? 1 : 0;
  return n;
}

class FilterAll : public ::testing::TestWithParam<std::string> {};

TEST_P(FilterAll, IsDeterministic) {
  const Image in = disk_image({96, 80}, {44, 38}, 24, {0.6f, 0.4f, 0.2f}, 0.2f);
  const FilterRun a = run_filter(in, GetParam());
  const FilterRun b = run_filter(in, GetParam());
  ASSERT_EQ(a.out.rgba.size(), b.out.rgba.size());
  EXPECT_EQ(0, std::memcmp(a.out.rgba.data(), b.out.rgba.data(), a.out.rgba.size() * sizeof(float)));
}

TEST_P(FilterAll, WritesItsWholeRectAndNothingOutside) {
  const Image in = disk_image({128, 96}, {50, 40}, 18, {0.3f, 0.7f, 0.5f}, 0.1f);
  const FilterInfo& info = find_filter(GetParam());
  const int fp = info.create()->footprint(validate(info.schema, {}));
  const FilterRun run = run_filter(in, GetParam());
  EXPECT_EQ(run.rect.min, covered_bounds(in).grown(fp, in.size).min);
  EXPECT_EQ(run.rect.max, covered_bounds(in).grown(fp, in.size).max);
  int outside_changed = 0, inside_sentinel = 0;
  for (int y = 0; y < in.size.y; ++y)
    for (int x = 0; x < in.size.x; ++x) {
      const bool inside = x >= run.rect.min.x && y >= run.rect.min.y && x < run.rect.max.x && y < run.rect.max.y;
      const bool sentinel = run.out.at(x, y) == kSentinel;
      outside_changed += !inside && !sentinel;
      inside_sentinel += inside && sentinel;
    }
  EXPECT_EQ(outside_changed, 0);
  EXPECT_EQ(inside_sentinel, 0);
  for (float v : run.out.rgba) ASSERT_TRUE(std::isfinite(v));
}

TEST_P(FilterAll, DrawsNoRingsAroundLonePoints) {
  const Image in = sparse_points({96, 96}, 7, {0.8f, 0.5f, 0.3f});
  const FilterRun run = run_filter(in, GetParam());
  if (GetParam() == "warp") {  // moves points (by design); may smear one over two pixels
    EXPECT_LE(covered_count(run.out), covered_count(in) * 2);
    return;
  }
  EXPECT_LE(covered_count(run.out), covered_count(in));
}

// Every numeric parameter at its maximum (the largest kernels and
// footprints), enums and bools at their defaults.
std::map<std::string, std::vector<double>> largest_params(const std::string& id) {
  std::map<std::string, std::vector<double>> params;
  for (const ParamSpec& spec : find_filter(id).schema.params)
    if (spec.type == ParamType::Float || spec.type == ParamType::Int) params[spec.name] = {spec.max};
  return params;
}

// The Renderer guarantees clean images only up to a filter's footprint
// beyond its rect: poisoning everything farther out (covered pixels of NaN
// colour, so any weight on them spreads NaN) must not change a byte.
void expect_reads_within_footprint(const std::string& id, const std::map<std::string, std::vector<double>>& params) {
  const FilterInfo& info = find_filter(id);
  const int fp = info.create()->footprint(validate(info.schema, params));
  const int side = 4 * fp + 48;  // leaves a poisoned border of >= 4 px
  const Image in = disk_image({side, side}, glm::vec2(float(side) / 2.0f), 10, {0.4f, 0.6f, 0.3f}, 0.1f);
  const Rect start = covered_bounds(in);
  const Rect readable = start.grown(2 * fp, in.size);
  Image poisoned = in;
  int poison = 0;
  for (int y = 0; y < in.size.y; ++y)
    for (int x = 0; x < in.size.x; ++x)
      if (x < readable.min.x || y < readable.min.y || x >= readable.max.x || y >= readable.max.y) {
        poisoned.set(x, y, glm::vec4(glm::vec3(std::nanf("")), 1.0f));  // any use spreads NaN
        ++poison;
      }
  ASSERT_GT(poison, 4 * side) << "the poisoned border exists";
  const FilterRun clean = run_filters(in, {{id, params}}, 0.0, 1, start);
  const FilterRun dirty = run_filters(poisoned, {{id, params}}, 0.0, 1, start);
  EXPECT_EQ(0, std::memcmp(clean.out.rgba.data(), dirty.out.rgba.data(), clean.out.rgba.size() * sizeof(float)))
      << id << ": reads beyond its footprint (" << fp << " px, " << poison << " poisoned pixels)";
}

TEST_P(FilterAll, ReadsNoFurtherThanItsFootprint) { expect_reads_within_footprint(GetParam(), {}); }

TEST_P(FilterAll, ReadsNoFurtherThanItsFootprintWithTheLargestParameters) {
  expect_reads_within_footprint(GetParam(), largest_params(GetParam()));
}

TEST_P(FilterAll, WritesItsWholeRectWithTheLargestParameters) {
  const Image in = disk_image({160, 128}, {80, 64}, 12, {0.3f, 0.7f, 0.5f}, 0.1f);
  const auto params = largest_params(GetParam());
  const FilterInfo& info = find_filter(GetParam());
  const int fp = info.create()->footprint(validate(info.schema, params));
  const FilterRun run = run_filters(in, {{GetParam(), params}});
  EXPECT_EQ(run.rect.min, covered_bounds(in).grown(fp, in.size).min);
  int outside_changed = 0, inside_sentinel = 0;
  for (int y = 0; y < in.size.y; ++y)
    for (int x = 0; x < in.size.x; ++x) {
      const bool inside = x >= run.rect.min.x && y >= run.rect.min.y && x < run.rect.max.x && y < run.rect.max.y;
      const bool sentinel = run.out.at(x, y) == kSentinel;
      outside_changed += !inside && !sentinel;
      inside_sentinel += inside && sentinel;
    }
  EXPECT_EQ(outside_changed, 0);
  EXPECT_EQ(inside_sentinel, 0);
  for (float v : run.out.rgba) ASSERT_TRUE(std::isfinite(v));
}

// Real points are splats of a few pixels: 3x3 ones, 10 px apart, must not
// get dark rims either (filters may fill or move, but draw no outlines).
TEST_P(FilterAll, DrawsNoRingsAroundLoneSplats) {
  Image in({100, 100});
  for (int y = 10; y < 90; y += 10)
    for (int x = 10; x < 90; x += 10)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) in.set(x + dx, y + dy, glm::vec4(0.9f, 0.7f, 0.5f, 1.0f));
  const FilterRun run = run_filter(in, GetParam());
  int dark_new = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const glm::vec4 o = run.out.at(x, y);
      if (o == kSentinel || in.at(x, y).a > 0.0f || o.a <= 0.0f) continue;
      dark_new += 0.2126f * o.r + 0.7152f * o.g + 0.0722f * o.b < 0.3f;
    }
  EXPECT_EQ(dark_new, 0);
}

INSTANTIATE_TEST_SUITE_P(FilterLibrary, FilterAll, ::testing::ValuesIn(filter_ids()),
                         [](const auto& p) { return p.param; });

// Through the Renderer: a dense plane and a sparse one, each filter alone.
class FilterThroughTheRenderer : public ::testing::TestWithParam<std::string> {};

TEST_P(FilterThroughTheRenderer, IsDeterministicAndStaysInItsGrownRect) {
  const glm::ivec2 size(160, 120);
  const Camera cam = front_camera({0, 0, 10}, size);
  auto scene_with = [&](Style style) {
    Scene scene;
    scene.segments.push_back(segment("plane", plane_cloud(-1.5, 1.0, -1.0, 0.8, 0, 0.03, {200, 120, 60}, {}, 0.02),
                                     style));
    return scene;
  };
  Renderer renderer;
  const RenderResult plain = renderer.render(scene_with(style_with({{"point_size", {2}}})), cam, settings(size));
  const Style styled = style_with({{"point_size", {2}}}, {{GetParam(), {}}});
  const RenderResult a = renderer.render(scene_with(styled), cam, settings(size));
  const RenderResult b = renderer.render(scene_with(styled), cam, settings(size));
  ASSERT_EQ(a.color.size(), b.color.size());
  EXPECT_EQ(0, std::memcmp(a.color.data(), b.color.data(), a.color.size() * sizeof(float)));
  Image cover(size);
  for (size_t i = 0; i < plain.color.size(); ++i) cover.rgba[i] = plain.color[i];
  const int fp = styled.filters[0].filter->footprint(styled.filters[0].params);
  const Rect grown = covered_bounds(cover).grown(fp, size);
  ASSERT_FALSE(grown.empty());
  int outside = 0, inside = 0;
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      const float alpha = a.color[4 * cover.index(x, y) + 3];
      const bool in = x >= grown.min.x && y >= grown.min.y && x < grown.max.x && y < grown.max.y;
      (in ? inside : outside) += alpha != 0.0f;
    }
  EXPECT_EQ(outside, 0);
  EXPECT_GT(inside, 1000);
}

INSTANTIATE_TEST_SUITE_P(FilterLibrary, FilterThroughTheRenderer, ::testing::ValuesIn(filter_ids()),
                         [](const auto& p) { return p.param; });

}  // namespace
