// Watercolor: region borders darker than interiors, holes painted over,
// the paper is deterministic, seeded and fixed to the surface.
#include <gtest/gtest.h>

#include <cstring>

#include "filter_images.h"
#include "render/renderer.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

float lum(glm::vec4 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Mean luminance of painted pixels within `band` px of unpainted ones (the
// border), and of those farther than 3 * band (the interior).
std::pair<double, double> border_and_interior(const Image& out, int band) {
  auto painted = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= out.size.x || y >= out.size.y) return false;
    const glm::vec4 c = out.at(x, y);
    return c != kSentinel && c.a > 0.0f;
  };
  double border = 0, interior = 0;
  int nb = 0, ni = 0;
  for (int y = 0; y < out.size.y; ++y)
    for (int x = 0; x < out.size.x; ++x) {
      if (!painted(x, y)) continue;
      int nearest = 1 << 20;
      const int reach = 3 * band;
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx)
          if (!painted(x + dx, y + dy)) nearest = std::min(nearest, std::max(std::abs(dx), std::abs(dy)));
      if (nearest <= band) border += lum(out.at(x, y)), ++nb;
      if (nearest > reach) interior += lum(out.at(x, y)), ++ni;
    }
  EXPECT_GT(nb, 50);
  EXPECT_GT(ni, 50);
  return {border / nb, interior / ni};
}

TEST(FilterWatercolor, DarkensRegionBordersRelativeToInteriors) {
  const Image in = disk_image({128, 128}, {64, 64}, 44, {0.55f, 0.7f, 0.85f});
  const FilterRun run = run_filter(in, "watercolor");
  maybe_dump(run.out, "watercolor_disk");
  const auto [border, interior] = border_and_interior(run.out, 2);
  EXPECT_LT(border, interior - 0.04) << "border " << border << " interior " << interior;
  const FilterRun flat = run_filter(in, "watercolor", {{"edge_darkening", {0}}});
  const auto [flat_border, flat_interior] = border_and_interior(flat.out, 2);
  EXPECT_NEAR(flat_border, flat_interior, 0.03) << "without darkening the rim is like the interior";
}

TEST(FilterWatercolor, DarkensColourEdgesInsideTheSegment) {
  const Image in = step_image({128, 80}, {0.9f, 0.6f, 0.3f}, {0.3f, 0.6f, 0.9f}, 0.0f);
  const FilterRun dark = run_filter(in, "watercolor", {{"wobble", {0}}, {"pigment_density", {0}}, {"granulation", {0}}});
  const FilterRun flat = run_filter(in, "watercolor", {{"wobble", {0}}, {"pigment_density", {0}}, {"granulation", {0}},
                                                        {"edge_darkening", {0}}});
  maybe_dump(dark.out, "watercolor_step");
  double at_edge = 0, inside = 0;
  for (int y = 24; y < 56; ++y) {
    for (int x = 62; x < 66; ++x) at_edge += lum(dark.out.at(x, y)) - lum(flat.out.at(x, y));
    for (int x : {30, 31, 96, 97}) inside += lum(dark.out.at(x, y)) - lum(flat.out.at(x, y));
  }
  at_edge /= 32 * 4, inside /= 32 * 4;
  EXPECT_LT(at_edge, -0.05) << "pigment gathers at the colour edge";
  EXPECT_NEAR(inside, 0.0, 1e-4) << "interiors are unchanged";
}

TEST(FilterWatercolor, PaintsOverSmallHolesAndKeepsLonePoints) {
  Image in({96, 96});
  for (int y = 16; y < 80; ++y)
    for (int x = 16; x < 80; ++x)
      if ((x + y) % 3 != 0) in.set(x, y, glm::vec4(0.4f, 0.5f, 0.6f, 1.0f));  // a third missing
  in.set(5, 5, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));  // a lone point
  const FilterRun run = run_filter(in, "watercolor", {{"wobble", {0}}});
  for (int y = 24; y < 72; ++y)
    for (int x = 24; x < 72; ++x) ASSERT_EQ(run.out.at(x, y).a, 1.0f) << x << "," << y;
  EXPECT_EQ(run.out.at(5, 5).a, 1.0f);
  EXPECT_GT(run.out.at(5, 5).r, 0.8f);
  EXPECT_EQ(run.out.at(6, 5).a, 0.0f) << "no rim around the lone point";
}

TEST(FilterWatercolor, PaperIsSeeded) {
  const Image in = disk_image({64, 64}, {32, 32}, 24, {0.5f, 0.5f, 0.5f});
  const FilterRun a = run_filter(in, "watercolor", {{"seed", {1}}});
  const FilterRun b = run_filter(in, "watercolor", {{"seed", {2}}});
  EXPECT_NE(0, std::memcmp(a.out.rgba.data(), b.out.rgba.data(), a.out.rgba.size() * sizeof(float)));
}


// Mean |a(x + shift, y) - b(x, y)| of the red channel in the middle.
double shifted_difference(const RenderResult& a, const RenderResult& b, glm::ivec2 size, int shift) {
  double sum = 0;
  int n = 0;
  for (int y = 30; y < size.y - 30; ++y)
    for (int x = 30; x < size.x - 30; ++x) {
      sum += std::abs(a.color[4 * (size_t(y) * size.x + size_t(x + shift))] - b.color[4 * (size_t(y) * size.x + size_t(x))]);
      ++n;
    }
  return sum / n;
}

TEST(FilterWatercolor, PaperAndPigmentMoveWithTheScan) {
  // Pan the camera by exactly 4 pixels over a plane of one colour: all the
  // watercolor draws there is paper and pigment, which must move with the
  // plane (before, the paper was fixed to the screen).
  const glm::ivec2 size(200, 150);
  const Camera first = front_camera({0, 0, 10}, size);
  const double pan = 4.0 / first.pixels_per_unit(10.0, size.y);
  const Camera second = front_camera({pan, 0, 10}, size);
  Renderer renderer;
  Scene scene;
  scene.segments.push_back(segment("plane", plane_cloud(-6, 6, -5, 5, 0, 0.02, {150, 110, 90}),
                                   style_with({{"point_size", {2}}},
                                              {{"watercolor", {{"granulation", {1}}, {"pigment_density", {1}}}}})));
  const RenderResult a = renderer.render(scene, first, settings(size));
  const RenderResult b = renderer.render(scene, second, settings(size));
  const double followed = shifted_difference(a, b, size, 4), stayed = shifted_difference(a, b, size, 0);
  EXPECT_LT(followed * 4, stayed) << "the paper follows the pan: " << followed << " vs " << stayed;
}

TEST(FilterWatercolor, PaperGrainIsSmoothNotBlocky) {
  // Value noise on a lattice of paper_scale px made square cells: steps
  // between neighbouring pixels as large as between far ones. Gradient
  // noise is smooth: neighbours differ far less than pixels 4 cells apart.
  const Image in = disk_image({128, 128}, {64, 64}, 200, {0.5f, 0.5f, 0.5f});
  const FilterRun run = run_filter(in, "watercolor", {{"wobble", {0}}, {"pigment_density", {0}}, {"granulation", {1}},
                                                      {"edge_darkening", {0}}, {"wet_in_wet", {0}}, {"paper_scale", {4}}});
  maybe_dump(run.out, "watercolor_grain");
  double near = 0, far = 0;
  int n = 0;
  for (int y = 16; y < 112; ++y)
    for (int x = 16; x < 96; ++x) {
      near += std::abs(lum(run.out.at(x + 1, y)) - lum(run.out.at(x, y)));
      far += std::abs(lum(run.out.at(x + 16, y)) - lum(run.out.at(x, y)));
      ++n;
    }
  EXPECT_GT(far / n, 0.02) << "the grain is visible";
  EXPECT_LT(near * 3, far) << "neighbours " << near / n << " vs 16 px apart " << far / n;
}

TEST(FilterWatercolor, WetInWetRunsColoursTogetherWithoutEdges) {
  // Two washes side by side: wet-in-wet mixes them near their border in
  // places (not everywhere: wet patches) and darkens the border less.
  const Image in = step_image({160, 96}, {0.9f, 0.6f, 0.3f}, {0.3f, 0.6f, 0.9f}, 0.0f);
  const std::map<std::string, std::vector<double>> base = {{"wobble", {0}}, {"pigment_density", {0}},
                                                           {"granulation", {0}}, {"density_scale", {16}}};
  auto with = [&](double wet) {
    auto p = base;
    p["wet_in_wet"] = {wet};
    return run_filter(in, "watercolor", p);
  };
  const FilterRun dry = with(0), wet = with(1);
  maybe_dump(wet.out, "watercolor_wet");
  int mixed_rows = 0;
  double dry_dark = 0, wet_dark = 0;
  for (int y = 8; y < 88; ++y) {
    // Just left of the border (x = 80): red-orange wash; wet, blue runs in.
    const glm::vec4 d = dry.out.at(77, y), w = wet.out.at(77, y);
    mixed_rows += w.b > d.b + 0.05f;
    dry_dark += lum(dry.out.at(79, y)) + lum(dry.out.at(80, y));
    wet_dark += lum(wet.out.at(79, y)) + lum(wet.out.at(80, y));
  }
  EXPECT_GT(mixed_rows, 8) << "colours run into each other in wet patches";
  EXPECT_LT(mixed_rows, 72) << "but not all along the border";
  EXPECT_GT(wet_dark, dry_dark) << "less edge darkening where wet";
}

}  // namespace
