// Renderer benchmarks on the 342k-point lion scan (data/lion_takanawa.ply):
//  - rasterizer throughput, compute vs GL_POINTS vs native, same data and view;
//  - one 1920x1080 engine frame with three styled segments (cartoon, warp,
//    plain) composited with depth inpainting, read back to the CPU.
// Run: build/bench/bench_render --benchmark_min_time=2
#include <benchmark/benchmark.h>

#include <glm/gtc/matrix_transform.hpp>

#include "io/readers.h"
#include "render/renderer.h"

using namespace pointnpr;

namespace {

struct LionScene {
  std::shared_ptr<PointCloud> whole;
  std::vector<std::shared_ptr<PointCloud>> slabs;  // three height bands
  Camera camera;
};

const LionScene& lion() {
  static const LionScene scene = [] {
    LionScene s;
    const PointData data = read_point_cloud(std::string(POINTNPR_REPO_DIR) + "/data/lion_takanawa.ply");
    const auto* colors = data.get<uint8_t>("colors");
    PointCloudInput in;
    in.positions = data.positions;
    in.colors = *colors;
    s.whole = std::make_shared<PointCloud>(in);
    // Three segments by height: ground, lower statue, upper statue.
    std::vector<std::vector<double>> pos(3);
    std::vector<std::vector<uint8_t>> col(3);
    for (size_t i = 0; i < data.num_points(); ++i) {
      const double z = data.positions[3 * i + 2];
      const size_t band = z < -2.6 ? 0 : (z < -1.0 ? 1 : 2);
      pos[band].insert(pos[band].end(), &data.positions[3 * i], &data.positions[3 * i + 3]);
      col[band].insert(col[band].end(), &(*colors)[3 * i], &(*colors)[3 * i + 3]);
    }
    for (int b = 0; b < 3; ++b) {
      PointCloudInput part;
      part.positions = pos[size_t(b)];
      part.colors = col[size_t(b)];
      s.slabs.push_back(std::make_shared<PointCloud>(part));
    }
    const glm::dvec3 center(-2.9, 3.9, -1.2), eye(-2.9 + 5.5, 3.9 - 5.5, 1.5);
    const glm::dmat4 view = glm::lookAt(eye, center, glm::dvec3(0, 0, 1));
    s.camera = Camera::perspective(glm::inverse(view), 35.0, 36.0, 24.0, SensorFit::Auto, 0, 0, 0.1, 100.0,
                                   {1920, 1080});
    return s;
  }();
  return scene;
}

// The points mark's rasterizers: its GL methods and native.
enum class RasterizerKind { Compute, GlPoints, Native };

RenderSettings frame_settings(const char* mode) {
  RenderSettings s;
  s.stage_timings = true;  // the stages' *_ms hold the GPU's work
  s.width = 1920;
  s.height = 1080;
  const auto& items = composite_schema().params[0].items;
  s.composite = validate(composite_schema(),
                         {{"mode", {double(std::find(items.begin(), items.end(), mode) - items.begin())}}});
  return s;
}

Style plain_style(double point_size, RasterizerKind kind) {
  Style style;
  // By the single value each had before gl_method (rasterizer gl with it).
  static const char* const names[] = {"compute", "gl_points", "native"};
  std::map<std::string, std::vector<double>> params{{"point_size", {point_size}}};
  const Schema& schema = find_mark("points").schema;
  set_enum_item(schema, *schema.find("rasterizer"), names[int(kind)], params);
  style.set_mark("points", params);
  return style;
}

// Time of the points mark alone (manual time), as points per second.
void BM_Rasterize(benchmark::State& state, RasterizerKind kind) {
  const LionScene& s = lion();
  Scene scene;
  scene.segments.push_back({"lion", plain_style(double(state.range(0)), kind), {{s.whole, glm::dmat4(1.0)}}});
  Renderer renderer;
  const RenderSettings settings = frame_settings("layering");
  renderer.render(scene, s.camera, settings);  // warm-up: upload, shader compile
  for (auto _ : state) {
    const RenderResult r = renderer.render(scene, s.camera, settings);
    state.SetIterationTime(r.stats.at("mark_ms") / 1000.0);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(s.whole->size()));
  state.counters["points"] = double(s.whole->size());
}
BENCHMARK_CAPTURE(BM_Rasterize, compute, RasterizerKind::Compute)->Arg(1)->Arg(3)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rasterize, gl_points, RasterizerKind::GlPoints)->Arg(1)->Arg(3)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rasterize, native, RasterizerKind::Native)->Arg(1)->Arg(3)->UseManualTime()->Unit(benchmark::kMillisecond);

// A whole engine frame: 3 segments, 3 styles, inpainting, read-back.
void BM_EngineFrame(benchmark::State& state, RasterizerKind kind) {
  const LionScene& s = lion();
  Scene scene;
  Style cartoon = plain_style(3.0, kind);
  cartoon.add_filter("cartoon", {});
  Style warp = plain_style(3.0, kind);
  warp.add_filter("warp", {{"amplitude", {4}}});
  scene.segments.push_back({"ground", plain_style(3.0, kind), {{s.slabs[0], glm::dmat4(1.0)}}});
  scene.segments.push_back({"lower", cartoon, {{s.slabs[1], glm::dmat4(1.0)}}});
  scene.segments.push_back({"upper", warp, {{s.slabs[2], glm::dmat4(1.0)}}});
  Renderer renderer;
  RenderSettings settings = frame_settings("inpaint");
  renderer.render(scene, s.camera, settings);
  std::map<std::string, double> stages;
  for (auto _ : state) {
    settings.time += 1.0 / 24.0;
    const RenderResult r = renderer.render(scene, s.camera, settings);
    for (const char* k : {"mark_ms", "filters_ms", "inpaint_ms", "composite_ms", "readback_ms"})
      stages[k] += r.stats.at(k);
  }
  for (auto& [k, v] : stages) state.counters[k] = v / double(state.iterations());
}
BENCHMARK_CAPTURE(BM_EngineFrame, compute, RasterizerKind::Compute)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_EngineFrame, gl_points, RasterizerKind::GlPoints)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_EngineFrame, native, RasterizerKind::Native)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
