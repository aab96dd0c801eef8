// XDoG edges: closed contours around solid regions, no rings around lone
// points, lines at colour edges only, colour and thickness as parameters.
#include <gtest/gtest.h>

#include <functional>
#include <queue>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

// Pixels painted in `edge` (opaque enough and close to its colour).
std::vector<uint8_t> edge_mask(const Image& out, glm::vec3 edge) {
  std::vector<uint8_t> m(size_t(out.size.x) * size_t(out.size.y), 0);
  for (int y = 0; y < out.size.y; ++y)
    for (int x = 0; x < out.size.x; ++x) {
      const glm::vec4 c = out.at(x, y);
      m[out.index(x, y)] = c != kSentinel && c.a >= 0.5f && glm::length(glm::vec3(c) - edge) < 0.15f;
    }
  return m;
}

// Connected components of `value` pixels (8- or 4-connected); `label` gets ids.
int components(const std::vector<uint8_t>& m, glm::ivec2 size, uint8_t value, bool eight,
               std::vector<int>* label = nullptr) {
  std::vector<int> lab(m.size(), -1);
  int n = 0;
  for (int y0 = 0; y0 < size.y; ++y0)
    for (int x0 = 0; x0 < size.x; ++x0) {
      const size_t i0 = size_t(y0) * size_t(size.x) + size_t(x0);
      if (m[i0] != value || lab[i0] >= 0) continue;
      std::queue<glm::ivec2> q;
      q.push({x0, y0});
      lab[i0] = n;
      while (!q.empty()) {
        const glm::ivec2 p = q.front();
        q.pop();
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if ((dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0)) continue;
            const glm::ivec2 r = p + glm::ivec2(dx, dy);
            if (r.x < 0 || r.y < 0 || r.x >= size.x || r.y >= size.y) continue;
            const size_t j = size_t(r.y) * size_t(size.x) + size_t(r.x);
            if (m[j] == value && lab[j] < 0) {
              lab[j] = n;
              q.push(r);
            }
          }
      }
      ++n;
    }
  if (label) *label = lab;
  return n;
}

void expect_one_closed_contour(const Image& out, glm::vec3 edge, glm::ivec2 inside) {
  const std::vector<uint8_t> m = edge_mask(out, edge);
  int count = 0;
  for (uint8_t v : m) count += v;
  EXPECT_GT(count, 100);
  EXPECT_EQ(components(m, out.size, 1, true), 1) << "edge pixels form one curve";
  std::vector<int> label;
  EXPECT_EQ(components(m, out.size, 0, false, &label), 2) << "the curve separates inside from outside";
  EXPECT_NE(label[out.index(inside.x, inside.y)], label[0]) << "the curve is closed";
}

TEST(FilterXDoG, FilledDiskGivesOneClosedContour) {
  const Image in = disk_image({128, 112}, {60, 54}, 34, {0.7f, 0.5f, 0.3f}, 0.02f);
  const FilterRun run = run_filter(in, "xdog");
  maybe_dump(run.out, "xdog_disk");
  expect_one_closed_contour(run.out, glm::vec3(0.0f), {60, 54});
}

TEST(FilterXDoG, EdgeColourIsAParameterWhiteOnOneSegment) {
  const Image in = disk_image({128, 112}, {60, 54}, 34, {0.2f, 0.5f, 0.3f});
  const FilterRun run = run_filter(in, "xdog", {{"edge_color", {1, 1, 1, 1}}});
  expect_one_closed_contour(run.out, glm::vec3(1.0f), {60, 54});
  EXPECT_EQ(components(edge_mask(run.out, glm::vec3(0.0f)), in.size, 1, true), 0) << "no black lines";
}

TEST(FilterXDoG, ThicknessWidensTheOutline) {
  const Image in = disk_image({128, 112}, {60, 54}, 30, {0.7f, 0.7f, 0.7f});
  auto ring = [&](double t) {
    const FilterRun run = run_filter(in, "xdog", {{"thickness", {t}}});
    int n = 0;
    for (uint8_t v : edge_mask(run.out, glm::vec3(0.0f))) n += v;
    return n;
  };
  const int thin = ring(1.0), thick = ring(4.0);
  // Ring area ~ 2 pi r w: four times the width, about four times the pixels.
  EXPECT_GT(thick, 3 * thin);
  EXPECT_LT(thick, 5 * thin);
}

TEST(FilterXDoG, SparsePointsGetNoLinesAtAll) {
  const Image in = sparse_points({96, 96}, 5, {0.6f, 0.6f, 0.6f});
  const FilterRun run = run_filter(in, "xdog", {{"thickness", {3}}});
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const glm::vec4 o = run.out.at(x, y);
      if (o == kSentinel) continue;
      ASSERT_EQ(o, in.at(x, y)) << x << "," << y;
    }
}

TEST(FilterXDoG, InkFollowsColourEdgesNotFlatRegions) {
  const Image in = step_image({128, 64}, {0.15f, 0.15f, 0.15f}, {0.85f, 0.85f, 0.85f}, 0.0f);
  const FilterRun run = run_filter(in, "xdog", {{"outline", {0}}});
  maybe_dump(run.out, "xdog_step");
  auto darkened = [&](int x) {
    int n = 0;
    for (int y = 16; y < 48; ++y) n += run.out.at(x, y).r < in.at(x, y).r - 0.05f;
    return n;
  };
  int near_edge = 0;
  for (int x = 60; x < 68; ++x) near_edge += darkened(x);
  EXPECT_GE(near_edge, 32) << "a line along the step";
  for (int x : {20, 30, 90, 100}) EXPECT_EQ(darkened(x), 0) << x;
}

TEST(FilterXDoG, LinesModeKeepsOnlyTheLines) {
  const Image in = disk_image({96, 96}, {48, 48}, 30, {0.7f, 0.5f, 0.3f});
  const FilterRun run = run_filter(in, "xdog", {{"mode", {1}}});
  EXPECT_EQ(run.out.at(48, 48), glm::vec4(0.0f)) << "flat interior becomes transparent";
  expect_one_closed_contour(run.out, glm::vec3(0.0f), {48, 48});
}

TEST(FilterXDoG, FlowGuidedLinesAreUnbrokenAndIgnoreNoise) {
  // FDoG (flow_length > 0): on a noisy step the line along the step is
  // unbroken, and the noise on either side makes under half the specks of
  // the isotropic DoG's (measured: 372 against 1236 px; the isotropic one
  // must make some, or the test says nothing).
  const Image in = step_image({128, 96}, {0.75f, 0.75f, 0.75f}, {0.35f, 0.35f, 0.35f}, 0.3f);
  auto ink = [&](const FilterRun& run, int x0, int x1) {
    int n = 0;
    for (int y = 16; y < 80; ++y)
      for (int x = x0; x < x1; ++x) n += run.out.at(x, y).a > 0.3f;
    return n;
  };
  const FilterRun iso = run_filter(in, "xdog", {{"outline", {0}}, {"mode", {1}}, {"sharpen", {60}}});
  const FilterRun flow =
      run_filter(in, "xdog", {{"outline", {0}}, {"mode", {1}}, {"sharpen", {60}}, {"flow_length", {3}}});
  maybe_dump(flow.out, "xdog_flow_step");
  int rows_with_line = 0;
  for (int y = 16; y < 80; ++y) {
    bool any = false;
    for (int x = 61; x < 67; ++x) any = any || flow.out.at(x, y).a > 0.3f;
    rows_with_line += any;
  }
  EXPECT_EQ(rows_with_line, 64) << "the line along the step has no gap";
  const int iso_specks = ink(iso, 16, 56) + ink(iso, 72, 112), flow_specks = ink(flow, 16, 56) + ink(flow, 72, 112);
  EXPECT_GT(iso_specks, 20) << "the isotropic DoG turns this noise into specks";
  EXPECT_LT(flow_specks * 2, iso_specks) << "flow " << flow_specks << " isotropic " << iso_specks;
}

}  // namespace
