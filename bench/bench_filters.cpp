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

void BM_Filter(benchmark::State& state, const std::string& id) {
  const Image& img = frame();
  run_filters(img, {{id, {}}});  // warm-up: shader compilation
  for (auto _ : state) {
    const FilterRun run = run_filters(img, {{id, {}}}, 0.0, 3);
    state.SetIterationTime(run.gpu_ms / 1000.0);
  }
  state.counters["Mpix/s"] =
      benchmark::Counter(double(img.size.x) * img.size.y * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

// Benchmarks are registered in main: the filter registry fills during static
// initialisation, in an order relative to this file that is unspecified.
int main(int argc, char** argv) {
  for (const FilterInfo* f : registered_filters())
    benchmark::RegisterBenchmark(("BM_Filter/" + f->schema.id).c_str(), BM_Filter, f->schema.id)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(2);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
