// Image parameters: colour grading through a look-up-table image read by
// OpenImageIO (strip and Hald layouts), the texture cache behind them, and
// watercolor's paper height map with granulation and dry brush.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <algorithm>
#include <fstream>
#include <functional>

#include "core/error.h"
#include "core/image_io.h"
#include "filter_images.h"
#include "gl/device.h"
#include "render/image_textures.h"

namespace {

using pointnpr::test::FilterRun;
using pointnpr::test::Step;
namespace fs = std::filesystem;

std::string temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pointnpr_lut_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

using Transform = std::function<glm::vec3(glm::vec3)>;

// An N²xN strip in the documented layout: top-left black, red across each
// slice, blue across slices, green downward.
std::string write_strip(const std::string& name, int n, const Transform& f) {
  pointnpr::Image img;
  img.width = n * n, img.height = n, img.channels = 3;
  img.pixels.resize(size_t(n) * n * n * 3);
  for (int g = 0; g < n; ++g)
    for (int b = 0; b < n; ++b)
      for (int r = 0; r < n; ++r) {
        const glm::vec3 out = f(glm::vec3(r, g, b) / float(n - 1));
        const int row_gl = n - 1 - g;  // Image rows are bottom first
        float* px = &img.pixels[(size_t(row_gl) * size_t(n * n) + size_t(b * n + r)) * 3];
        px[0] = out.r, px[1] = out.g, px[2] = out.b;
      }
  const std::string path = temp_file(name);
  pointnpr::write_image(path, img, false);
  return path;
}

// A Hald CLUT of level L (L³ x L³ pixels, N = L² entries per axis).
std::string write_hald(const std::string& name, int level, const Transform& f) {
  const int n = level * level, w = level * level * level;
  pointnpr::Image img;
  img.width = w, img.height = w, img.channels = 3;
  img.pixels.resize(size_t(w) * w * 3);
  for (int i = 0; i < n * n * n; ++i) {
    const int r = i % n, g = (i / n) % n, b = i / (n * n);
    const glm::vec3 out = f(glm::vec3(r, g, b) / float(n - 1));
    const int x = i % w, row_gl = w - 1 - i / w;
    float* px = &img.pixels[(size_t(row_gl) * w + size_t(x)) * 3];
    px[0] = out.r, px[1] = out.g, px[2] = out.b;
  }
  const std::string path = temp_file(name);
  pointnpr::write_image(path, img, false);
  return path;
}

FilterRun grade(const pointnpr::test::Image& in, const std::string& lut, double strength = 1.0) {
  return pointnpr::test::run_filters(in, {Step{"color_grade", {{"lut_strength", {strength}}}, {{"lut", lut}}}});
}

// Max |out - expected(in)| over covered pixels.
float max_error(const pointnpr::test::Image& in, const FilterRun& run, const Transform& expected) {
  float worst = 0.0f;
  int covered = 0;
  for (int y = 0; y < in.size.y; ++y)
    for (int x = 0; x < in.size.x; ++x) {
      const glm::vec4 c = in.at(x, y);
      if (c.a <= 0.0f) continue;
      ++covered;
      const glm::vec3 want = expected(glm::vec3(c));
      const glm::vec4 got = run.out.at(x, y);
      worst = std::max(worst, [](glm::vec3 d) { return std::max({d.x, d.y, d.z}); }(glm::abs(glm::vec3(got) - want)));
      EXPECT_EQ(got.a, c.a);
    }
  EXPECT_GT(covered, 1000);
  return worst;
}

const Transform kIdentity = [](glm::vec3 c) { return c; };
const Transform kSwapRedBlue = [](glm::vec3 c) { return glm::vec3(c.b, c.g, c.r); };

TEST(FilterColorGradeLut, IdentityStripAndHaldLeaveColoursUnchanged) {
  const pointnpr::test::Image in = pointnpr::test::gradient_image({64, 48});
  // 8-bit files: entries are off by up to half a step (0.002).
  EXPECT_LT(max_error(in, grade(in, write_strip("identity_strip.png", 16, kIdentity)), kIdentity), 4e-3f);
  EXPECT_LT(max_error(in, grade(in, write_hald("identity_hald.png", 4, kIdentity)), kIdentity), 4e-3f);
}

TEST(FilterColorGradeLut, ALutThatSwapsChannelsIsAppliedTrilinearly) {
  const pointnpr::test::Image in = pointnpr::test::gradient_image({64, 48});
  // A 2-entry strip: any linear map is exact between entries (trilinear).
  EXPECT_LT(max_error(in, grade(in, write_strip("swap2.png", 2, kSwapRedBlue)), kSwapRedBlue), 4e-3f);
  const std::string hald = write_hald("swap_hald.png", 4, kSwapRedBlue);
  EXPECT_LT(max_error(in, grade(in, hald), kSwapRedBlue), 4e-3f);
  const Transform half = [](glm::vec3 c) { return 0.5f * (c + kSwapRedBlue(c)); };
  EXPECT_LT(max_error(in, grade(in, hald, 0.5), half), 4e-3f);
}

TEST(FilterColorGradeLut, FilesAreReadOnceAndAgainWhenChanged) {
  const pointnpr::test::Image in = pointnpr::test::gradient_image({64, 48});
  const std::string path = write_strip("cached.png", 8, kIdentity);
  auto loads = [] { return pointnpr::gl::Device::instance().run([] { return pointnpr::standalone_image_textures().loads(); }); };
  grade(in, path);
  const size_t after_first = loads();
  grade(in, path);
  EXPECT_EQ(loads(), after_first);
  // Rewritten with another size: read again, and the new table is used.
  write_strip("cached.png", 2, kSwapRedBlue);
  const FilterRun swapped = grade(in, path);
  EXPECT_EQ(loads(), after_first + 1);
  EXPECT_LT(max_error(in, swapped, kSwapRedBlue), 4e-3f);
}

TEST(FilterColorGradeLut, BadFilesAreErrorsNamingTheFile) {
  const pointnpr::test::Image in = pointnpr::test::gradient_image({64, 48});
  // Missing: refused when the style is built.
  const pointnpr::FilterInfo& info = pointnpr::find_filter("color_grade");
  EXPECT_THROW(pointnpr::validate(info.schema, {}, {{"lut", "/nonexistent/look.png"}}), pointnpr::ParameterError);
  // A path for a number and a number for a path.
  EXPECT_THROW(pointnpr::validate(info.schema, {}, {{"exposure", "/tmp"}}), pointnpr::ParameterError);
  EXPECT_THROW(pointnpr::validate(info.schema, {{"lut", {1.0}}}), pointnpr::ParameterError);
  // Not a LUT layout (30x20), and not an image at all.
  pointnpr::Image odd;
  odd.width = 30, odd.height = 20, odd.channels = 3;
  odd.pixels.assign(30 * 20 * 3, 0.5f);
  const std::string odd_path = temp_file("odd.png");
  pointnpr::write_image(odd_path, odd, false);
  try {
    grade(in, odd_path);
    ADD_FAILURE() << "a 30x20 LUT was accepted";
  } catch (const pointnpr::Error& e) {
    EXPECT_NE(std::string(e.what()).find("30x20"), std::string::npos) << e.what();
  }
  const std::string text = temp_file("not_an_image.png");
  { std::ofstream(text) << "hello"; }
  try {
    grade(in, text);
    ADD_FAILURE() << "a text file was accepted as a LUT";
  } catch (const pointnpr::Error& e) {
    EXPECT_NE(std::string(e.what()).find("not_an_image.png"), std::string::npos) << e.what();
  }
}

// A paper height map: left half peaks (1), right half valleys (0).
std::string write_half_paper() {
  pointnpr::Image img;
  img.width = 64, img.height = 64, img.channels = 1;
  img.pixels.resize(64 * 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) img.pixels[size_t(y) * 64 + size_t(x)] = x < 32 ? 1.0f : 0.0f;
  const std::string path = temp_file("half_paper.png");
  pointnpr::write_image(path, img, false);
  return path;
}

float luminance(glm::vec4 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

// Watercolor on a flat 128x128 colour block with only the paper effect on.
FilterRun paint(const std::map<std::string, std::vector<double>>& params, const std::string& paper) {
  const pointnpr::test::Image in = pointnpr::test::disk_image({128, 128}, {64, 64}, 200, {0.4f, 0.55f, 0.8f});
  std::map<std::string, std::vector<double>> all = {{"wobble", {0}},         {"pigment_density", {0}},
                                                    {"edge_darkening", {0}}, {"granulation", {0}},
                                                    {"abstraction", {0}},    {"paper_scale", {1}}};
  for (const auto& [k, v] : params) all[k] = v;
  return pointnpr::test::run_filters(in, {Step{"watercolor", all, {{"paper", paper}}}});
}

TEST(FilterWatercolorPaper, PigmentSettlesInTheValleysOfThePaperImage) {
  const std::string paper = write_half_paper();
  const FilterRun run = paint({{"granulation", {1}}}, paper);
  // Tiled 64 px paper at 1 px per texel: x mod 64 < 32 is a peak. Compare
  // columns away from the half boundaries (bilinear blends 1 px there).
  double peaks = 0, valleys = 0;
  int n = 0;
  for (int y = 10; y < 118; ++y)
    for (int x : {8, 20, 72, 84}) peaks += luminance(run.out.at(x, y)), valleys += luminance(run.out.at(x + 32, y)), ++n;
  EXPECT_LT(valleys / n, peaks / n - 0.08) << "valleys " << valleys / n << " peaks " << peaks / n;
  const FilterRun plain = paint({}, paper);
  EXPECT_NEAR(luminance(plain.out.at(20, 60)), luminance(plain.out.at(52, 60)), 1e-5f) << "no granulation, no grain";
}

TEST(FilterWatercolorPaper, DryBrushLeavesPaperInTheValleysOnly) {
  const std::string paper = write_half_paper();
  const glm::vec4 paper_colour(1.0f, 0.0f, 1.0f, 1.0f);  // magenta: easy to find
  const FilterRun dry = paint({{"dry_brush", {1}}, {"paper_color", {1, 0, 1, 1}}}, paper);
  int paper_in_valleys = 0, paper_on_peaks = 0, valleys = 0;
  for (int y = 10; y < 118; ++y)
    for (int x = 0; x < 128; ++x) {
      const int u = x % 64;
      if (u < 2 || (u > 29 && u < 34) || u > 61) continue;  // blended half boundaries
      const bool shows_paper = glm::length(glm::vec3(dry.out.at(x, y)) - glm::vec3(paper_colour)) < 0.05f;
      if (u >= 32) ++valleys, paper_in_valleys += shows_paper;
      else paper_on_peaks += shows_paper;
    }
  EXPECT_EQ(paper_on_peaks, 0);
  EXPECT_GT(paper_in_valleys, valleys / 2) << paper_in_valleys << " of " << valleys;
  // Without dry brush no pixel shows the paper.
  const FilterRun wet = paint({{"paper_color", {1, 0, 1, 1}}}, paper);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      ASSERT_GT(glm::length(glm::vec3(wet.out.at(x, y)) - glm::vec3(paper_colour)), 0.3f) << x << "," << y;
}

TEST(FilterWatercolorPaper, ProceduralPaperShowsMoreAsTheBrushDries) {
  const pointnpr::test::Image in = pointnpr::test::disk_image({160, 160}, {80, 80}, 60, {0.3f, 0.5f, 0.7f});
  auto paper_fraction = [&](double dry) {
    const FilterRun run = pointnpr::test::run_filters(
        in, {Step{"watercolor", {{"dry_brush", {dry}}, {"paper_color", {1, 0, 1, 1}}}, {}}});
    int painted = 0, paper = 0;
    for (int y = 0; y < 160; ++y)
      for (int x = 0; x < 160; ++x) {
        if (in.at(x, y).a <= 0.0f) continue;
        const glm::vec4 c = run.out.at(x, y);
        ++painted;
        paper += c.r > 0.8f && c.g < 0.3f && c.b > 0.8f;
      }
    return double(paper) / painted;
  };
  const double none = paper_fraction(0.0), some = paper_fraction(0.5), most = paper_fraction(1.0);
  EXPECT_EQ(none, 0.0);
  EXPECT_GT(some, 0.01);
  EXPECT_GT(most, some + 0.1) << none << " " << some << " " << most;
  EXPECT_LT(most, 0.9) << "pigment stays on the peaks";
}

}  // namespace
