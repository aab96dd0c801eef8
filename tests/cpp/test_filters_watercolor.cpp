// Watercolor: region borders darker than interiors, holes painted over,
// the paper is deterministic and seeded.
#include <gtest/gtest.h>

#include <cstring>

#include "filter_images.h"

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

}  // namespace
