// The filter chain's depth-aware gap fill (shaders/gap_fill.comp, issue 40):
// filters that read neighbourhoods see no background inside a surface, a
// depth jump is closed only by the farther surface, and back points seen through a front
// surface's gaps give way to it. The harness's view is orthographic, one
// scene unit per pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "filter_images.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Image empty_with_depth(glm::ivec2 size) {
  Image img(size);
  img.depth.assign(size_t(size.x) * size_t(size.y), kInf);
  return img;
}

void put(Image& img, int x, int y, glm::vec4 c, float depth) {
  img.set(x, y, c);
  img.depth[img.index(x, y)] = depth;
}

// Kuwahara keeps each pixel's coverage as its input has it: what the chain
// hands it decides what is covered.
const Step kOil{"kuwahara", {{"radius", {3.0}}, {"impasto", {0.0}}}};

TEST(GapFill, NeighbourhoodFiltersSeeNoBackgroundInsideASurface) {
  const glm::vec4 colour(0.3f, 0.6f, 0.9f, 1.0f);
  Image in = empty_with_depth({96, 96});
  for (int y = 20; y < 76; ++y)
    for (int x = 20; x < 76; ++x)
      if (hash_noise(x, y, 9) > -0.4f) put(in, x, y, colour, 10.0f + 0.01f * float(x));  // 30 % missing, sloped
  int holes_in = 0;
  for (int y = 23; y < 73; ++y)
    for (int x = 23; x < 73; ++x) holes_in += in.at(x, y).a == 0.0f;
  ASSERT_GT(holes_in, 300);
  for (const Step& step : {kOil, Step{"watercolor", {}}, Step{"cartoon", {}}, Step{"xdog", {}}}) {
    const FilterRun run = run_filters(in, {step});
    int holes_out = 0;
    for (int y = 23; y < 73; ++y)
      for (int x = 23; x < 73; ++x) holes_out += run.out.at(x, y).a < 0.5f;
    EXPECT_EQ(holes_out, 0) << step.id;
    // Nothing grows beyond the surface (outlines aside, which cartoon and
    // xdog draw on purpose): the gap fill adds no coverage outside it.
    if (step.id != "kuwahara") continue;
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x) {
        if ((x < 19 || x >= 77 || y < 19 || y >= 77) && run.out.at(x, y) != kSentinel) {
          ASSERT_EQ(run.out.at(x, y).a, 0.0f) << x << "," << y;
        }
      }
  }
}

TEST(GapFill, ADepthJumpIsClosedOnlyByTheFartherSurfaceWithinTheReach) {
  // Two surfaces side by side with a gap between them: one surface (equal
  // depths) closes a 4 px gap. A statue 90 units in front of a wall never
  // paints into it; the wall runs on behind the statue's edge (a scanner
  // beside the camera misses a band of it as wide as the statue stands in
  // front), so it fills the gap, with or without a known spacing, as far
  // as the search reaches (16 px at most: a 40 px gap stays open).
  const glm::vec4 statue(0.8f, 0.2f, 0.2f, 1.0f), wall(0.2f, 0.2f, 0.8f, 1.0f);
  struct Case {
    float right_depth, spacing;
    int gap, open;
  };
  for (const Case c : {Case{10.0f, 0.0f, 4, 0}, Case{100.0f, 0.0f, 4, 0}, Case{100.0f, 2.4f, 4, 0},
                       Case{100.0f, 0.0f, 40, 20 * 40}}) {
    Image in = empty_with_depth({96, 48});
    for (int y = 8; y < 40; ++y)
      for (int x = 8; x < 88; ++x) {
        if (x < 30) put(in, x, y, statue, 10.0f);
        if (x >= 30 + c.gap) put(in, x, y, wall, c.right_depth);
      }
    in.spacing = c.spacing;
    const FilterRun run = run_filters(in, {kOil});
    int open = 0;
    for (int y = 14; y < 34; ++y)
      for (int x = 30; x < 30 + c.gap; ++x) {
        const glm::vec4 o = run.out.at(x, y);
        open += o.a < 0.5f;
        if (o.a >= 0.5f && c.right_depth > 10.0f) {
          ASSERT_LT(o.r, 0.3f) << "the statue paints into the gap at " << x;
        }
      }
    EXPECT_EQ(open, c.open) << "depth " << c.right_depth << ", spacing " << c.spacing << ", gap " << c.gap;
  }
}

TEST(GapFill, BackPointsSeenThroughAGapGiveWayToTheFrontSurface) {
  // A front surface with sensor noise of +-3 px-sizes in depth (more than
  // the steepest slope allows over a pixel), a 6x6 gap in it, and a dark
  // back splat 190 units behind seen through the gap (farther than the
  // front's steepest slope reaches over the fill's search).
  const glm::vec4 back(0.05f, 0.05f, 0.05f, 1.0f);
  auto scene = [&](bool noisy) {
    Image in = empty_with_depth({64, 64});
    for (int y = 12; y < 52; ++y)
      for (int x = 12; x < 52; ++x) {
        const bool hole = x >= 29 && x < 35 && y >= 29 && y < 35;
        const bool back_splat = x >= 30 && x < 33 && y >= 30 && y < 33;
        const glm::vec4 front((x + y) % 2 ? 0.9f : 0.6f, 0.8f, 0.7f, 1.0f);
        if (!hole) put(in, x, y, front, 10.0f + (noisy ? 3.0f * hash_noise(x, y, 3) : 0.0f));
        if (back_splat) put(in, x, y, back, 200.0f);
      }
    return in;
  };
  const FilterRun noisy = run_filters(scene(true), {kOil});
  for (int y = 29; y < 35; ++y)
    for (int x = 29; x < 35; ++x) {
      const glm::vec4 o = noisy.out.at(x, y);
      ASSERT_GE(o.a, 0.5f) << x << "," << y;
      ASSERT_GT(o.r, 0.5f) << "the dark back point shows through at " << x << "," << y;
    }
  // The front surface's own noise is not taken for points behind it: away
  // from the gap, the noisy depths give the same picture as flat ones.
  const FilterRun flat = run_filters(scene(false), {kOil});
  for (int y = 12; y < 19; ++y)
    for (int x = 12; x < 52; ++x) ASSERT_EQ(noisy.out.at(x, y), flat.out.at(x, y)) << x << "," << y;
}

TEST(GapFill, TheScansSpacingClosesScanLineGapsWiderThanItsSplatsAndKeepsItsHoles) {
  // An aerial tile's sampling: scan lines 7 px apart, a 3x2 px splat every
  // 3 px along each (gaps of 5 px between the lines: wider than the
  // splats, so without the spacing the surface does not run on for half a
  // gap and nothing closes), and a 24 px square without points (a hole in
  // the scan, wider than twice its spacing) that stays open.
  Image in = empty_with_depth({96, 96});
  const auto in_hole = [](int x, int y) { return x >= 36 && x < 60 && y >= 36 && y < 60; };
  for (int y = 8; y < 88; y += 7)
    for (int x = 8; x < 88; x += 3)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 3; ++dx)
          if (!in_hole(x + dx, y + dy)) put(in, x + dx, y + dy, glm::vec4(0.7f, 0.4f, 0.3f, 1.0f), 10.0f);
  // Open pixels of the lattice away from the hole, or deep inside it (its
  // border, 3 px either side and to the scan lines above and below it, is
  // enclosed along fewer lines: either way).
  const auto open_pixels = [&](const Image& out, bool hole) {
    int n = 0;
    for (int y = 12; y < 84; ++y)
      for (int x = 12; x < 84; ++x) {
        const bool near_hole = x >= 33 && x < 63 && y >= 26 && y < 70;
        const bool deep_in_hole = x >= 39 && x < 57 && y >= 39 && y < 57;
        if (hole ? deep_in_hole : !near_hole) n += out.at(x, y).a < 0.5f;
      }
    return n;
  };
  const FilterRun unknown = run_filters(in, {kOil});
  EXPECT_GT(open_pixels(unknown.out, false), 1000) << "without the spacing the gaps stay";
  // The lattice's mean distance to a point's 7 nearest neighbours (what the
  // renderer hands over): 3, 3, 6, 6, 7, 7 and sqrt(3^2 + 7^2) px, in the
  // harness's view of one unit per pixel.
  in.spacing = (3.0f + 3.0f + 6.0f + 6.0f + 7.0f + 7.0f + std::sqrt(58.0f)) / 7.0f;
  const FilterRun known = run_filters(in, {kOil});
  EXPECT_EQ(open_pixels(known.out, false), 0) << "the gaps between the scan's samples close";
  EXPECT_EQ(open_pixels(known.out, true), 18 * 18) << "a hole wider than twice the spacing stays open";
}

TEST(GapFill, EachPointsOwnSpacingClosesWhereTheScanIsSparserThanTheSegments) {
  // The scan-line lattice above (lines 7 px apart, splats 3x2 px every 3 px)
  // with the segment's spacing a denser part's (1 px: its lines' gaps stay
  // open by it). Each point's own spacing is handed over on the lower half
  // only: its gaps close there, the upper half's stay, and a 24 px hole
  // stays open.
  Image in = empty_with_depth({96, 96});
  in.pixel_spacing.assign(size_t(96 * 96), 0.0f);
  const float lattice = (3.0f + 3.0f + 6.0f + 6.0f + 7.0f + 7.0f + std::sqrt(58.0f)) / 7.0f;
  const auto in_hole = [](int x, int y) { return x >= 36 && x < 60 && y >= 8 && y < 32; };
  for (int y = 1; y < 95; y += 7)
    for (int x = 4; x < 92; x += 3)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 3; ++dx)
          if (!in_hole(x + dx, y + dy)) {
            put(in, x + dx, y + dy, glm::vec4(0.7f, 0.4f, 0.3f, 1.0f), 10.0f);
            if (y + dy < 48) in.pixel_spacing[in.index(x + dx, y + dy)] = lattice;
          }
  in.spacing = 1.0f;
  const auto open_pixels = [](const Image& out, int x0, int x1, int y0, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) n += out.at(x, y).a < 0.5f;
    return n;
  };
  const FilterRun run = run_filters(in, {kOil});
  EXPECT_EQ(open_pixels(run.out, 12, 84, 36, 44) + open_pixels(run.out, 12, 30, 4, 36) +
                open_pixels(run.out, 66, 84, 4, 36),
            0)
      << "the lower half's gaps close by its points' own spacing";
  EXPECT_GT(open_pixels(run.out, 12, 84, 52, 88), 1000) << "the upper half's stay by the segment's";
  EXPECT_EQ(open_pixels(run.out, 39, 57, 11, 29), 18 * 18) << "a hole wider than twice the spacing stays open";
}

TEST(GapFill, APinholeItsClosedNeighboursSurroundCloses) {
  // Eight splat pixels a knight's move from a centre (a lattice of lone
  // returns): each line through the centre meets none of them, so the
  // search leaves it, but it closes each of its 8 neighbours (2 lines each).
  // The pinhole pass then closes the centre too, and the surface grows no
  // further than the ring.
  Image in = empty_with_depth({48, 48});
  const glm::ivec2 c{24, 24};
  for (const glm::ivec2 d : {glm::ivec2(1, 2), glm::ivec2(2, 1), glm::ivec2(2, -1), glm::ivec2(1, -2),
                             glm::ivec2(-1, -2), glm::ivec2(-2, -1), glm::ivec2(-2, 1), glm::ivec2(-1, 2)})
    put(in, c.x + d.x, c.y + d.y, glm::vec4(0.4f, 0.6f, 0.3f, 1.0f), 10.0f);
  in.spacing = 2.0f;
  const FilterRun run = run_filters(in, {kOil});
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) EXPECT_GE(run.out.at(c.x + dx, c.y + dy).a, 0.5f) << dx << "," << dy;
  int covered = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      if (run.out.at(x, y).a < 0.5f) continue;
      ++covered;
      EXPECT_TRUE(std::abs(x - c.x) <= 2 && std::abs(y - c.y) <= 2) << x << "," << y;
    }
  EXPECT_GE(covered, 17);
}

}  // namespace

TEST(GapFill, ANotchsMouthClosesAsTheWallsAroundItDoAndAWideBayStaysOpen) {
  // A solid surface's top edge (y = 40) with notches cut into it: 3 px deep
  // and 4 px wide (every pixel of it is enclosed along one line only, by
  // its walls: its mouth), 1 px wide and 1 px deep (a scallop), and a bay
  // 24 px wide. The notches close; the bay, wider than any splat's reach,
  // stays open, and nothing grows above the edge or beside the corners.
  Image in = empty_with_depth({96, 96});
  const auto notch = [](int x, int y) {
    return (x >= 20 && x < 24 && y < 43) || (x == 32 && y < 41) || (x >= 50 && x < 74 && y < 46);
  };
  for (int y = 40; y < 80; ++y)
    for (int x = 10; x < 86; ++x)
      if (!notch(x, y)) put(in, x, y, glm::vec4(0.2f, 0.5f, 0.3f, 1.0f), 10.0f + 0.02f * float(y));
  const FilterRun run = run_filters(in, {kOil});
  for (int y = 40; y < 43; ++y)
    for (int x = 20; x < 24; ++x) EXPECT_GE(run.out.at(x, y).a, 0.5f) << "the notch at " << x << "," << y;
  EXPECT_GE(run.out.at(32, 40).a, 0.5f) << "the scallop";
  int bay_open = 0;
  for (int y = 40; y < 46; ++y)
    for (int x = 58; x < 66; ++x) bay_open += run.out.at(x, y).a < 0.5f;
  EXPECT_EQ(bay_open, 8 * 6) << "the bay's middle";
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x)
      if ((y < 40 || x < 10 || x >= 86 || y >= 80) && run.out.at(x, y) != kSentinel) {
        ASSERT_EQ(run.out.at(x, y).a, 0.0f) << "grown at " << x << "," << y;
      }
}
