// The points mark's rasterizers at scan scale (issue 14): 10M points of a
// wavy terrain filling a 1920x1080 frame, plain points, side by side with
// a reference: a plain two-thread scatter of the same projected points into
// a uint64 depth-key buffer (one pixel per point, atomic minimum), the
// machine's limit for any rasterizer that keeps the nearest point.
//
// Goals: native >= 40M points/s at 2 px, and >= 0.8 x the reference at 1 px.
// Run: build/bench/bench_rasterizer --benchmark_min_time=2
// (POINTNPR_BENCH_POINTS: another cloud size.)
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "render/renderer.h"

using namespace pointnpr;

namespace {

constexpr int kWidth = 1920, kHeight = 1080;
constexpr int kThreads = 2;  // the reference's, and every path's here

struct Terrain {
  std::shared_ptr<PointCloud> cloud;
  Camera camera;
};

const Terrain& terrain() {
  static const Terrain t = [] {
    const char* env = std::getenv("POINTNPR_BENCH_POINTS");
    const size_t n = env ? size_t(std::atoll(env)) : size_t(10'000'000);
    std::vector<double> pos(3 * n);
    std::vector<uint8_t> col(3 * n);
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (size_t i = 0; i < n; ++i) {
      const double x = -50.0 + 100.0 * u(rng), y = -30.0 + 60.0 * u(rng);
      pos[3 * i] = x;
      pos[3 * i + 1] = y;
      pos[3 * i + 2] = 2.0 * std::sin(0.2 * x) * std::cos(0.3 * y);
      for (int c = 0; c < 3; ++c) col[3 * i + size_t(c)] = uint8_t(rng() & 0xff);
    }
    PointCloudInput in;
    in.positions = pos;
    in.colors = col;
    Terrain out;
    out.cloud = std::make_shared<PointCloud>(in);
    // Looking down at the terrain from above: it fills the frame.
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0, -12, 40), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 1));
    out.camera = Camera::perspective(glm::inverse(view), 30.0, 36.0, 24.0, SensorFit::Auto, 0, 0, 0.1, 500.0,
                                     {kWidth, kHeight});
    return out;
  }();
  return t;
}

RenderSettings frame_settings() {
  RenderSettings s;
  s.stage_timings = true;  // mark_ms holds the GPU's work
  s.width = kWidth;
  s.height = kHeight;
  return s;
}

// The points mark alone (mark_ms: clear, draw, coverage bounds), as points per second.
void BM_PointsMark(benchmark::State& state, const char* rasterizer) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kThreads);
  const Terrain& t = terrain();
  // By the single value each had before gl_method (rasterizer gl with it).
  std::map<std::string, std::vector<double>> params{{"point_size", {double(state.range(0))}}};
  const Schema& schema = find_mark("points").schema;
  set_enum_item(schema, *schema.find("rasterizer"), rasterizer, params);
  Style style;
  style.set_mark("points", params);
  Scene scene;
  scene.segments.push_back({"terrain", style, {{t.cloud, glm::dmat4(1.0)}}});
  Renderer renderer;
  const RenderSettings settings = frame_settings();
  double covered = 0.0;
  const RenderResult warm = renderer.render(scene, t.camera, settings);  // upload, shader compile
  for (size_t i = 0; i < warm.segment_index.size(); ++i) covered += warm.segment_index[i] >= 0;
  std::map<std::string, double> stages;
  for (auto _ : state) {
    const RenderResult r = renderer.render(scene, t.camera, settings);
    state.SetIterationTime(r.stats.at("mark_ms") / 1000.0);
    for (const auto& [k, v] : r.stats)
      if (k.starts_with("native_") || k.starts_with("tmp_")) stages[k] += v;
  }
  for (auto& [k, v] : stages) state.counters[k] = v / double(state.iterations());
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(t.cloud->size()));
  state.counters["points"] = double(t.cloud->size());
  state.counters["covered"] = covered / double(warm.segment_index.size());
}
// The machine is shared: run with --benchmark_repetitions=5
// --benchmark_enable_random_interleaving=true and read the "min" rows
// (the least disturbed run of each).
double fastest(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
BENCHMARK_CAPTURE(BM_PointsMark, native, "native")
    ->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond)->ComputeStatistics("min", fastest);
BENCHMARK_CAPTURE(BM_PointsMark, compute, "compute")
    ->Arg(1)->Arg(2)->Iterations(2)->UseManualTime()->Unit(benchmark::kMillisecond)->ComputeStatistics("min", fastest);
BENCHMARK_CAPTURE(BM_PointsMark, gl_points, "gl_points")
    ->Arg(1)->Arg(2)->Iterations(2)->UseManualTime()->Unit(benchmark::kMillisecond)->ComputeStatistics("min", fastest);

// The reference: each chunk's points by one float matrix to pixels, one
// pixel each, atomic minimum of (depth bits << 32 | index); two threads.
void BM_ScatterReference(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, kThreads);
  const Terrain& t = terrain();
  const PointCloud& cloud = *t.cloud;
  const Camera& cam = t.camera;
  std::vector<glm::mat4> clip_from_chunk, view_from_chunk;
  for (const PointChunk& c : cloud.chunks()) {
    const glm::dmat4 view = cam.view_from_world * glm::translate(glm::dmat4(1.0), c.origin);
    view_from_chunk.push_back(glm::mat4(view));
    clip_from_chunk.push_back(glm::mat4(cam.projection * view));
  }
  const size_t pixels = size_t(kWidth) * size_t(kHeight);
  std::unique_ptr<uint64_t[]> keys(new uint64_t[pixels]);
  const glm::vec3* positions = cloud.local_positions().data();
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    std::fill(keys.get(), keys.get() + pixels, ~uint64_t(0));
    tbb::parallel_for(tbb::blocked_range<size_t>(0, cloud.chunks().size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t ci = r.begin(); ci < r.end(); ++ci) {
        const PointChunk& c = cloud.chunks()[ci];
        const glm::mat4& m = clip_from_chunk[ci];
        const glm::mat4& v = view_from_chunk[ci];
        for (uint32_t i = c.first; i < c.first + c.count; ++i) {
          const glm::vec3 p = positions[i];
          const float depth = -(v[0][2] * p.x + v[1][2] * p.y + v[2][2] * p.z + v[3][2]);
          const float w = m[0][3] * p.x + m[1][3] * p.y + m[2][3] * p.z + m[3][3];
          const float x = ((m[0][0] * p.x + m[1][0] * p.y + m[2][0] * p.z + m[3][0]) / w * 0.5f + 0.5f) * kWidth;
          const float y = ((m[0][1] * p.x + m[1][1] * p.y + m[2][1] * p.z + m[3][1]) / w * 0.5f + 0.5f) * kHeight;
          if (!(depth > 0.0f && x >= 0.0f && x < float(kWidth) && y >= 0.0f && y < float(kHeight))) continue;
          uint32_t bits;
          std::memcpy(&bits, &depth, 4);
          const uint64_t packed = uint64_t(bits) << 32 | i;
          std::atomic_ref<uint64_t> slot(keys[size_t(y) * kWidth + size_t(x)]);
          uint64_t cur = slot.load(std::memory_order_relaxed);
          while (packed < cur && !slot.compare_exchange_weak(cur, packed, std::memory_order_relaxed)) {
          }
        }
      }
    });
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    benchmark::DoNotOptimize(keys[pixels / 2]);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(cloud.size()));
}
BENCHMARK(BM_ScatterReference)->UseManualTime()->Unit(benchmark::kMillisecond)->ComputeStatistics("min", fastest);

}  // namespace

BENCHMARK_MAIN();
