// Renderer behaviour on synthetic scenes with known ground truth.
#include <gtest/gtest.h>
#include <iostream>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "geometry/analysis.h"
#include "gl/device.h"
#include "gl/gl.h"
#include "gl/shaders.h"
#include "scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

constexpr glm::ivec2 kSize{320, 240};

// Seed 000 Fig. 12 set-up: a sparse near segment (cartoon: outlines and
// filled gaps) in front of a dense far one that is drawn later.
Scene fig12_scene(glm::dvec3 offset = glm::dvec3(0.0)) {
  Scene scene;
  const Style cartoon = style_with({{"point_size", {3}}}, {{"cartoon", {}}});
  scene.segments.push_back(segment("near", plane_cloud(-1.2, 0.4, -0.6, 0.6, -5, 0.03, {230, 60, 40}, offset, 0.02),
                                   cartoon));
  scene.segments.push_back(segment("far", plane_cloud(-2, 3, -1.5, 1.5, -10, 0.05, {40, 60, 230}, offset),
                                   style_with({{"point_size", {3}}})));
  return scene;
}

// Pixels well inside the near plane's projection whose front segment is not
// the near one. Ground truth from the camera model: half-width at 5 m is
// 5 * 18 / 50 = 1.8 m over 160 px.
int wrong_front_pixels(const RenderResult& r) {
  int wrong = 0;
  const double px_per_m = 160.0 / 1.8;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      const double wx = (x + 0.5 - 160.0) / px_per_m, wy = (y + 0.5 - 120.0) / px_per_m;
      const double margin = 3.0 / px_per_m;
      const bool near_inside = wx > -1.2 + margin && wx < 0.4 - margin && wy > -0.6 + margin && wy < 0.6 - margin;
      if (near_inside && r.segment_index[size_t(y) * size_t(r.width) + size_t(x)] != 0) ++wrong;
    }
  return wrong;
}

bool same_bytes(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

size_t count_differing(const std::vector<float>& a, const std::vector<float>& b) {
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}

}  // namespace

TEST(Render, CompositingModesOrderAsInFig12) {
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize);
  const Scene scene = fig12_scene();
  const int layering = wrong_front_pixels(renderer.render(scene, cam, settings(kSize, "layering")));
  const int depth_test = wrong_front_pixels(renderer.render(scene, cam, settings(kSize, "depth_test")));
  const int inpaint = wrong_front_pixels(renderer.render(scene, cam, settings(kSize, "inpaint")));
  // Listing 1 as the paper has it.
  Scene paper = scene;
  for (Segment& seg : paper.segments) seg.style.inpaint = validate(inpaint_schema(), {{"method", {1}}});
  const int inpaint_paper = wrong_front_pixels(renderer.render(paper, cam, settings(kSize, "inpaint")));
  // About 130 x 100 pixels lie inside the near plane.
  EXPECT_GT(layering, 10000);
  EXPECT_GT(layering, depth_test);
  EXPECT_GT(depth_test, 500);  // filled gaps without depth let the far plane through
  EXPECT_LT(inpaint * 20, depth_test) << "layering " << layering << " depth test " << depth_test;
  EXPECT_LT(inpaint_paper * 20, depth_test);
  std::cout << "Fig. 12 wrong pixels: layering " << layering << ", depth test " << depth_test << ", inpaint "
            << inpaint << " (paper " << inpaint_paper << ")\n";
}

TEST(Render, SurfaceInpaintingKeepsCoveredDepthsAndStrictNeverPaintsOverOtherPoints) {
  // A small square in front of a large plane; the square's style draws
  // outlines beyond its silhouette (cartoon, width 3) and changes colours.
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize);
  auto scene_with = [](double method) {
    Scene scene;
    Style outlined = style_with({{"point_size", {4}}}, {{"cartoon", {{"outline_width", {3}}}}});
    outlined.inpaint = validate(inpaint_schema(), {{"method", {method}}});
    scene.segments.push_back(segment("square", plane_cloud(-0.3, 0.3, -0.3, 0.3, -5, 0.01, {230, 60, 40}), outlined));
    scene.segments.push_back(segment("plane", plane_cloud(-0.2, 3, -1.5, 1.5, -10, 0.02, {40, 60, 230}),
                                     style_with({{"point_size", {4}}})));
    return scene;
  };
  Scene plain = scene_with(0);
  plain.segments[0].style = style_with({{"point_size", {4}}});
  const RenderResult reference = renderer.render(plain, cam, settings(kSize, "depth_test"));
  const RenderResult tested = renderer.render(scene_with(0), cam, settings(kSize, "depth_test"));
  const RenderResult surface = renderer.render(scene_with(0), cam, settings(kSize, "inpaint"));
  const RenderResult strict = renderer.render(scene_with(2), cam, settings(kSize, "inpaint"));
  size_t covered = 0, tested_wrong = 0, strict_wrong = 0, surface_over_plane = 0, depth_moved = 0;
  size_t surface_over_background = 0, strict_over_background = 0;
  for (size_t i = 0; i < reference.segment_index.size(); ++i) {
    const int ref = reference.segment_index[i];
    if (ref >= 0) {
      ++covered;
      tested_wrong += tested.segment_index[i] != ref;
      strict_wrong += strict.segment_index[i] != ref;
      // The square's outline in front of the plane behind it.
      surface_over_plane += ref == 1 && surface.segment_index[i] == 0;
      // Where the square's points are in front, the depth is theirs.
      if (ref == 0 && surface.segment_index[i] == 0) depth_moved += surface.depth[i] != reference.depth[i];
    } else {
      surface_over_background += surface.segment_index[i] == 0;
      strict_over_background += strict.segment_index[i] == 0;
    }
  }
  EXPECT_GT(covered, 20000u);
  EXPECT_EQ(depth_moved, 0u);
  EXPECT_GT(surface_over_plane, 300u);     // outlines keep their place in front
  EXPECT_LE(strict_wrong, tested_wrong);   // strict: never worse than the depth test
  // Both draw the outline where nothing else is (left of the plane, x < -0.2 m).
  EXPECT_GT(surface_over_background, 100u);
  EXPECT_EQ(strict_over_background, surface_over_background);
}

TEST(Render, InpaintingWithoutCoveredNeighboursKeepsBackgroundDepth) {
  // One point, displaced 20 px by a warp: its new pixels have no covered
  // pixel within the inpainting radius. Listing 1 would divide 0 by 0.
  Renderer renderer;
  std::vector<double> pos = {0.0, 0.0, -5.0};
  PointCloudInput in;
  in.positions = pos;
  auto cloud = std::make_shared<PointCloud>(in);
  Scene scene;
  scene.segments.push_back(segment(
      "lonely", cloud,
      style_with({{"point_size", {2}}, {"color_source", {3}}},
                 {{"warp", {{"amplitude", {20}}, {"wavelength", {4096}}, {"direction", {90}}, {"phase", {90}}}}},
                 {{"radius", {2}}})));
  const RenderResult r = renderer.render(scene, front_camera({0, 0, 0}, kSize), settings(kSize, "inpaint"));
  int drawn = 0;
  for (size_t i = 0; i < r.depth.size(); ++i) {
    ASSERT_FALSE(std::isnan(r.depth[i])) << "pixel " << i;
    ASSERT_FALSE(std::isnan(r.color[4 * i + 3])) << "pixel " << i;
    if (r.color[4 * i + 3] > 0.0f) {
      ++drawn;
      EXPECT_EQ(r.depth[i], kBackgroundDepth) << "pixel " << i;
    }
  }
  EXPECT_GE(drawn, 1);
  // The point's own pixel was moved away.
  EXPECT_EQ(r.color[4 * (120 * 320 + 160) + 3], 0.0f);
}

TEST(Render, WarpAnimatesWithTimeAndIsDeterministic) {
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize);
  Scene scene;
  scene.segments.push_back(segment("wave", plane_cloud(-1, 1, -0.6, 0.6, -5, 0.02, {200, 200, 40}),
                                   style_with({{"point_size", {3}}}, {{"warp", {{"amplitude", {8}}, {"wavelength", {60}}}}})));
  const RenderResult t0 = renderer.render(scene, cam, settings(kSize, "inpaint", 0.0));
  const RenderResult t0_again = renderer.render(scene, cam, settings(kSize, "inpaint", 0.0));
  const RenderResult t1 = renderer.render(scene, cam, settings(kSize, "inpaint", 0.375));
  EXPECT_TRUE(same_bytes(t0.color, t0_again.color));
  EXPECT_TRUE(same_bytes(t0.depth, t0_again.depth));
  EXPECT_GT(count_differing(t0.color, t1.color), 1000u);
}

TEST(Render, TranslationByAMillionMetresChangesNothing) {
  Renderer renderer;
  const glm::dvec3 offset(1e6, 5e6, 0.0);
  const RenderResult at_origin = renderer.render(fig12_scene(), front_camera({0, 0, 0}, kSize), settings(kSize));
  const RenderResult far_away = renderer.render(fig12_scene(offset), front_camera(offset, kSize), settings(kSize));
  EXPECT_EQ(count_differing(at_origin.color, far_away.color), 0u);
  EXPECT_EQ(at_origin.segment_index, far_away.segment_index);
}

TEST(Render, SegmentsOneCentimetreApartAtOneKilometreCompositeInOrder) {
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize, 0.01, 5000.0);
  auto front = plane_cloud(-400, 400, -300, 300, -1000.0, 2.0, {255, 0, 0});
  auto back = plane_cloud(-400, 400, -300, 300, -1000.01, 2.0, {0, 0, 255});
  for (RasterizerKind kind : {RasterizerKind::Compute, RasterizerKind::GlPoints, RasterizerKind::Native}) {
    for (const char* mode : {"depth_test", "inpaint"}) {
      for (bool back_last : {true, false}) {
        Scene scene;
        const Style s = style_with({{"point_size", {4}}});
        scene.segments.push_back(back_last ? segment("front", front, s) : segment("back", back, s));
        scene.segments.push_back(back_last ? segment("back", back, s) : segment("front", front, s));
        const int front_index = back_last ? 0 : 1;
        const RenderResult r = renderer.render(with_rasterizer(scene, kind), cam, settings(kSize, mode, 0.0));
        size_t covered = 0, wrong = 0;
        for (int32_t idx : r.segment_index) {
          covered += idx >= 0;
          wrong += idx >= 0 && idx != front_index;
        }
        EXPECT_GT(covered, size_t(kSize.x * kSize.y) * 9 / 10);
        EXPECT_EQ(wrong, 0u) << mode << " rasterizer " << int(kind);
      }
    }
  }
}

TEST(Render, ComputeAndGlPointsRasterizersAgree) {
  Renderer renderer;
  const Camera cam = front_camera({0, 0, 0}, kSize);
  Scene scene;
  scene.segments.push_back(segment("a", plane_cloud(-1.2, 0.4, -0.6, 0.6, -5, 0.03, {230, 60, 40}, {}, 0.02),
                                   style_with({{"point_size", {3}}})));
  scene.segments.push_back(segment("b", plane_cloud(-2, 3, -1.5, 1.5, -10, 0.11, {40, 60, 230}, {}, 0.05),
                                   style_with({{"point_size", {5}}})));
  const RenderResult c = renderer.render(with_rasterizer(scene, RasterizerKind::Compute), cam, settings(kSize, "depth_test", 0.0));
  const RenderResult g = renderer.render(with_rasterizer(scene, RasterizerKind::GlPoints), cam, settings(kSize, "depth_test", 0.0));
  size_t either = 0, mismatch = 0, index_mismatch = 0;
  for (size_t i = 0; i < c.segment_index.size(); ++i) {
    const bool cc = c.color[4 * i + 3] > 0, gc = g.color[4 * i + 3] > 0;
    either += cc || gc;
    mismatch += cc != gc;
    index_mismatch += c.segment_index[i] != g.segment_index[i];
  }
  ASSERT_GT(either, 20000u);
  // Tolerance: 0.5% of covered pixels (splat borders exactly on pixel centres).
  EXPECT_LE(mismatch * 200, either) << mismatch << " of " << either;
  EXPECT_LE(index_mismatch * 200, either) << index_mismatch << " of " << either;
}

TEST(Render, ChunksBehindTheCameraAreCulled) {
  Renderer renderer;
  Scene scene;
  scene.segments.push_back(segment("behind", plane_cloud(-1, 1, -1, 1, 5, 0.05, {255, 255, 255}),
                                   style_with({{"point_size", {2}}})));
  const RenderResult r = renderer.render(scene, front_camera({0, 0, 0}, kSize), settings(kSize));
  EXPECT_GT(r.stats.at("chunks_total"), 0.0);
  EXPECT_EQ(r.stats.at("chunks_culled"), r.stats.at("chunks_total"));
  for (int32_t idx : r.segment_index) ASSERT_EQ(idx, -1);
}

TEST(Render, OnlyAttributesTheStyleUsesAreUploadedOnce) {
  Renderer renderer;
  auto cloud = plane_cloud(-1, 1, -1, 1, -5, 0.05, {10, 20, 30});
  const Camera cam = front_camera({0, 0, 0}, kSize);
  Scene constant;
  constant.segments.push_back(segment("c", cloud, style_with({{"color_source", {3}}})));
  renderer.render(constant, cam, settings(kSize));
  EXPECT_TRUE(renderer.uploaded_attributes(cloud->id()).empty());  // positions only
  const uint64_t uploads_after_positions = renderer.upload_count();
  Scene rgb;
  rgb.segments.push_back(segment("c", cloud, style_with({{"color_source", {0}}})));
  renderer.render(rgb, cam, settings(kSize));
  EXPECT_EQ(renderer.uploaded_attributes(cloud->id()), AttributeSet{{AttributeKind::Color}});
  EXPECT_EQ(renderer.upload_count(), uploads_after_positions + 1);
  renderer.render(rgb, cam, settings(kSize));  // redraw: nothing new
  EXPECT_EQ(renderer.upload_count(), uploads_after_positions + 1);
  EXPECT_EQ(renderer.cached_clouds(), 1u);
}

namespace {
// A unit sphere 5 m in front of the camera, evenly sampled (Fibonacci).
std::shared_ptr<PointCloud> sphere_cloud(bool with_normals) {
  std::vector<double> pos;
  std::vector<float> nrm;
  const int n = 12000;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), a = 2.399963229728653 * i;
    const glm::dvec3 d(r * std::cos(a), r * std::sin(a), z);
    pos.insert(pos.end(), {d.x, d.y, d.z - 5.0});
    nrm.insert(nrm.end(), {float(d.x), float(d.y), float(d.z)});
  }
  PointCloudInput in;
  in.positions = pos;
  if (with_normals) in.normals = nrm;
  return std::make_shared<PointCloud>(in);
}
float gray_at(const RenderResult& r, int x, int y) { return r.color[4 * (size_t(y) * size_t(r.width) + size_t(x))]; }
}  // namespace

TEST(Render, DiffuseShadingUsesNormalsEstimatedOnlyWhenAStyleAsks) {
  const Camera cam = front_camera({0, 0, 0}, kSize);
  const Style flat = style_with({{"point_size", {3}}, {"color_source", {3}}, {"color", {1, 1, 1, 1}}});
  const Style lit = style_with({{"point_size", {3}}, {"color_source", {3}}, {"color", {1, 1, 1, 1}},
                                {"shading", {1}}, {"shading_strength", {1}}, {"light_elevation", {0}}});
  for (RasterizerKind kind : {RasterizerKind::Compute, RasterizerKind::GlPoints, RasterizerKind::Native}) {
    Renderer renderer;
    auto cloud = sphere_cloud(false);
    Scene scene;
    scene.segments.push_back(segment("ball", cloud, flat));
    const RenderResult plain = renderer.render(with_rasterizer(scene, kind), cam, settings(kSize, "inpaint", 0.0));
    EXPECT_TRUE(cloud->analysis().computed().empty());  // a style without shading estimates nothing
    EXPECT_FALSE(renderer.uploaded_attributes(cloud->id()).count({AttributeKind::Normal, 16}));
    scene.segments[0].style = lit;
    const RenderResult shaded = renderer.render(with_rasterizer(scene, kind), cam, settings(kSize, "inpaint", 0.0));
    const auto computed = cloud->analysis().computed();
    EXPECT_NE(std::find(computed.begin(), computed.end(), "normals:16:consistent"), computed.end());
    EXPECT_TRUE(renderer.uploaded_attributes(cloud->id()).count({AttributeKind::Normal, 16}));
    // Light from the camera: the centre faces it, 0.9 of the way to the rim
    // the surface is turned 64 degrees away (cos = 0.44).
    const int rim_x = 160 + 82;
    EXPECT_NEAR(gray_at(plain, 160, 120), gray_at(plain, rim_x, 120), 1e-6f);
    EXPECT_GT(gray_at(shaded, 160, 120), 0.95f * gray_at(plain, 160, 120));
    EXPECT_LT(gray_at(shaded, rim_x, 120), 0.6f * gray_at(plain, rim_x, 120));
    EXPECT_GT(gray_at(shaded, rim_x, 120), 0.05f);
    // A second frame reuses the uploaded normals.
    const uint64_t uploads = renderer.upload_count();
    renderer.render(with_rasterizer(scene, kind), cam, settings(kSize, "inpaint", 0.0));
    EXPECT_EQ(renderer.upload_count(), uploads);
    // Two styles shading one cloud from different k keep a buffer each:
    // after the first frame, nothing is estimated or uploaded again.
    Scene two = scene;
    Style coarse = lit;
    std::map<std::string, std::vector<double>> coarse_params{
        {"point_size", {3}}, {"color_source", {3}}, {"shading", {1}}, {"normal_neighbors", {8}}};
    set_rasterizer(coarse_params, kind);
    coarse.set_mark("points", coarse_params);
    two.segments.push_back(segment("ball again", cloud, coarse));
    renderer.render(with_rasterizer(two, kind), cam, settings(kSize, "inpaint", 0.0));
    const uint64_t both = renderer.upload_count();
    EXPECT_EQ(both, uploads + 1);
    renderer.render(with_rasterizer(two, kind), cam, settings(kSize, "inpaint", 0.0));
    EXPECT_EQ(renderer.upload_count(), both);

    // A cloud with normals of its own is lit by them; nothing is estimated.
    auto own = sphere_cloud(true);
    scene.segments[0].instances[0].cloud = own;
    const RenderResult given = renderer.render(with_rasterizer(scene, kind), cam, settings(kSize, "inpaint", 0.0));
    EXPECT_TRUE(own->analysis().computed().empty());
    EXPECT_NEAR(gray_at(given, rim_x, 120), gray_at(shaded, rim_x, 120), 0.05f);
  }
}

TEST(Render, MissingAttributeFallsBackToConstantColorWithAWarning) {
  Renderer renderer;
  std::vector<double> pos = {0, 0, -5};
  PointCloudInput in;
  in.positions = pos;
  Scene scene;
  scene.segments.push_back(segment("no colors", std::make_shared<PointCloud>(in),
                                   style_with({{"point_size", {4}}, {"color", {0, 1, 0, 1}}, {"color_source", {0}}})));
  const RenderResult r = renderer.render(scene, front_camera({0, 0, 0}, kSize), settings(kSize));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0],
            "1 object has no colors for its style's colour source (a cloud of segment 'no colors'); drawn in the "
            "constant colour");
  const float* c = &r.color[4 * (120 * 320 + 160)];
  EXPECT_FLOAT_EQ(c[1], 1.0f);
  EXPECT_FLOAT_EQ(c[0], 0.0f);
}

TEST(Render, BackgroundGoesUnderThePremultipliedImage) {
  Renderer renderer;
  Scene empty;
  RenderSettings s = settings(kSize);
  s.background = {0.2, 0.4, 0.6, 1.0};
  const RenderResult r = renderer.render(empty, front_camera({0, 0, 0}, kSize), s);
  EXPECT_FLOAT_EQ(r.color[0], 0.2f);
  EXPECT_FLOAT_EQ(r.color[2], 0.6f);
  EXPECT_FLOAT_EQ(r.color[3], 1.0f);
  EXPECT_EQ(r.depth[0], kBackgroundDepth);
}

TEST(Render, ProgressCanCancel) {
  Renderer renderer;
  RenderSettings s = settings(kSize);
  int calls = 0;
  s.progress = [&calls](double, const std::string&) { return ++calls < 2; };
  EXPECT_THROW(renderer.render(fig12_scene(), front_camera({0, 0, 0}, kSize), s), RenderCancelled);
  EXPECT_EQ(calls, 2);
}

TEST(Render, InvalidSizesAreRefused) {
  Renderer renderer;
  EXPECT_THROW(renderer.render(Scene{}, front_camera({0, 0, 0}, kSize), settings({0, 10})), ParameterError);
  EXPECT_THROW(renderer.render(Scene{}, front_camera({0, 0, 0}, kSize), settings({40000, 10})), ParameterError);
}

TEST(GLDevice, TheHostsCurrentContextAndItsStateSurviveARender) {
  // Stand in for Blender: a context of our own, current on this thread.
  EGLDisplay display = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  ASSERT_NE(display, EGL_NO_DISPLAY);
  ASSERT_TRUE(eglInitialize(display, nullptr, nullptr));
  ASSERT_TRUE(eglBindAPI(EGL_OPENGL_API));
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext host = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
  ASSERT_NE(host, EGL_NO_CONTEXT);
  ASSERT_TRUE(eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, host));
  glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
  GLuint host_fbo = 0;
  glGenFramebuffers(1, &host_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, host_fbo);

  Renderer renderer;
  renderer.render(fig12_scene(), front_camera({0, 0, 0}, kSize), settings(kSize));

  EXPECT_EQ(eglGetCurrentContext(), host);
  GLfloat clear[4];
  glGetFloatv(GL_COLOR_CLEAR_VALUE, clear);
  EXPECT_FLOAT_EQ(clear[0], 0.25f);
  EXPECT_FLOAT_EQ(clear[2], 0.75f);
  GLint bound = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &bound);
  EXPECT_EQ(GLuint(bound), host_fbo);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  glDeleteFramebuffers(1, &host_fbo);
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, host);
}

TEST(GLDevice, DescribesItsContext) {
  const gl::DeviceInfo& info = gl::Device::instance().info();
  EXPECT_NE(info.version.find("4."), std::string::npos);
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_GE(info.max_texture_size, 4096);
}

TEST(GLDevice, ShaderCompileErrorsBecomeGLErrorsWithTheLog) {
  const std::string dir = ::testing::TempDir() + "/pointnpr_bad_shaders";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/broken.comp") << "layout(local_size_x = 1) in;\nvoid main() { undeclared_thing = 1; }\n";
  const std::string previous = gl::shader_dir();
  gl::set_shader_dir(dir);
  try {
    gl::Device::instance().run([] {
      gl::ShaderLibrary library;
      library.compute("broken.comp");
    });
    ADD_FAILURE() << "no error";
  } catch (const GLError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.comp failed to compile"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("undeclared_thing"), std::string::npos) << e.what();
  }
  gl::set_shader_dir(previous);
}
