// Milliseconds per filter at 1920x1080 (every registered filter, default
// parameters), on a frame covered but for a 16 px margin: colour gradients
// with noise and a varying depth. Only the filter's GPU work is timed (the
// filter chain run through the test harness, glFinish'ed; upload and read
// back excluded), as the Renderer runs it on a segment that fills the frame.
// Each benchmark: 2 iterations of 3 runs, mean time per run.
// Run: POINTNPR_SHADER_DIR=shaders build/bench/bench_filters
#include <benchmark/benchmark.h>

#include <cmath>

#include "../tests/cpp/filter_images.h"
#include "../tests/cpp/scene_builders.h"

using namespace pointnpr;
using namespace pointnpr::test;

namespace {

const Image& frame() {
  static const Image img = [] {
    Image f = gradient_image({1920, 1080}, 16);
    f.depth.assign(size_t(1920) * 1080, std::numeric_limits<float>::infinity());
    for (int y = 16; y < 1080 - 16; ++y)
      for (int x = 16; x < 1920 - 16; ++x)
        f.depth[f.index(x, y)] = 10.0f + 3.0f * std::sin(float(x) * 0.01f) + ((x / 200 + y / 200) % 2 ? 2.0f : 0.0f);
    return f;
  }();
  return img;
}

void BM_Filter(benchmark::State& state, const std::string& id, bool fill_gaps) {
  const Image& img = frame();
  run_filters(img, {{id, {}}}, 0.0, 1, std::nullopt, fill_gaps);  // warm-up: shader compilation
  for (auto _ : state) {
    const FilterRun run = run_filters(img, {{id, {}}}, 0.0, 3, std::nullopt, fill_gaps);
    state.SetIterationTime(run.gpu_ms / 1000.0);
  }
  state.counters["Mpix/s"] =
      benchmark::Counter(double(img.size.x) * img.size.y * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

// Cost follows coverage (issue 5): the frame split into K x K segments that
// do not overlap, each with the filter, against one segment covering the
// same area. Reports the Renderer's filters_ms (all segments' filter
// chains) for the frame; it should stay within 1.5x of K = 1.
void BM_SegmentsVsFrame(benchmark::State& state, const std::string& id) {
  const int k = int(state.range(0));
  const glm::ivec2 size(1920, 1080);
  const Camera cam = front_camera({0, 0, 10}, size);
  const double half_w = 10.0 * 18.0 / 50.0, half_h = half_w * 1080.0 / 1920.0;
  const double gap = 0.12;  // ~30 px between segments: more than twice any default footprint
  Scene scene;
  const Style style = style_with({{"point_size", {3}}}, {{id, {}}});
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const double x0 = -half_w + 2.0 * half_w * i / k, x1 = -half_w + 2.0 * half_w * (i + 1) / k;
      const double y0 = -half_h + 2.0 * half_h * j / k, y1 = -half_h + 2.0 * half_h * (j + 1) / k;
      scene.segments.push_back(segment("s", plane_cloud(x0 + (k > 1 ? gap / 2 : 0), x1 - (k > 1 ? gap / 2 : 0),
                                                        y0 + (k > 1 ? gap / 2 : 0), y1 - (k > 1 ? gap / 2 : 0), 0,
                                                        0.008, {150, 120, 90}, {}, 0.004),
                                       style));
    }
  Renderer renderer;
  RenderSettings s = settings(size, "layering");
  s.stage_timings = true;  // filters_ms holds the GPU's work
  renderer.render(scene, cam, s);  // warm-up
  double filters_ms = 0;
  for (auto _ : state) {
    const RenderResult r = renderer.render(scene, cam, s);
    filters_ms = r.stats.at("filters_ms");
    state.SetIterationTime(filters_ms / 1000.0);
  }
  state.counters["segments"] = double(k * k);
}

}  // namespace

// Benchmarks are registered in main: the filter registry fills during static
// initialisation, in an order relative to this file that is unspecified.
int main(int argc, char** argv) {
  // Filters that read neighbourhoods also without the chain's gap fill
  // (BM_Filter/<id>/no_gap_fill), so its cost is measured side by side.
  for (const FilterInfo* f : registered_filters())
    for (const bool fill : {true, false}) {
      if (!fill && !f->create()->reads_neighbourhood()) continue;
      benchmark::RegisterBenchmark(("BM_Filter/" + f->schema.id + (fill ? "" : "/no_gap_fill")).c_str(), BM_Filter,
                                   f->schema.id, fill)
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(2);
    }
  for (const char* id : {"blur", "xdog", "watercolor"})
    benchmark::RegisterBenchmark((std::string("BM_SegmentsVsFrame/") + id).c_str(), BM_SegmentsVsFrame, id)
        ->Arg(1)
        ->Arg(2)
        ->Arg(4)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(2);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
