// The all-points kNN, the step that dominates normal estimation: the grid
// search of geometry/neighbors.cpp (knn_all) against the same queries in
// nanoflann's k-d tree (the search it replaced: the tree's build plus one
// kNN per point, in parallel as before), and the whole normal estimation
// (PCA included). The tree search keeps the grid's exact (distance, index)
// order (a small cost per query over nanoflann's own result set). On the
// aerial LiDAR HD tile and the lion scan, k = 10,
// 16, 30. Wall time, both cores.
// Run: build/bench/bench_knn --benchmark_min_time=2 --benchmark_repetitions=5
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>

#include <string>

#include "geometry/local_points.h"
#include "geometry/neighbors.h"
#include "geometry/normals.h"
#include "io/readers.h"

using namespace pointnpr;
using namespace pointnpr::geometry;

namespace {

const LocalPoints& scan(const std::string& file) {
  static std::map<std::string, LocalPoints> loaded;
  auto it = loaded.find(file);
  if (it == loaded.end())
    it = loaded.emplace(file, LocalPoints::from(read_point_cloud(std::string(POINTNPR_REPO_DIR) + "/data/" + file).positions))
             .first;
  return it->second;
}

void BM_GridKnn(benchmark::State& state, const std::string& file) {
  const LocalPoints& pts = scan(file);
  const int k = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(knn_all(pts, k));
  state.counters["Mpoints/s"] = benchmark::Counter(double(pts.size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_KdTreeKnn(benchmark::State& state, const std::string& file) {
  const LocalPoints& pts = scan(file);
  const size_t k = size_t(state.range(0)), n = pts.size();
  std::vector<uint32_t> index(n * k);
  std::vector<float> dist2(n * k);
  for (auto _ : state) {
    const KdTree tree(pts.points);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) tree.knn(pts.points[i], k, &index[i * k], &dist2[i * k]);
    });
    benchmark::DoNotOptimize(index.data());
  }
  state.counters["Mpoints/s"] = benchmark::Counter(double(n) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Normals(benchmark::State& state, const std::string& file) {
  const LocalPoints& pts = scan(file);
  const int k = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(pca(pts, knn_all(pts, k)));
  state.counters["Mpoints/s"] = benchmark::Counter(double(pts.size()) * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

#define POINTNPR_KNN_BENCH(fn, file, name) \
  BENCHMARK_CAPTURE(fn, name, std::string(file))->Arg(10)->Arg(16)->Arg(30)->Unit(benchmark::kMillisecond)->UseRealTime()

POINTNPR_KNN_BENCH(BM_GridKnn, "lidarhd_myria3d_870000_6618000_subset.las", aerial);
POINTNPR_KNN_BENCH(BM_KdTreeKnn, "lidarhd_myria3d_870000_6618000_subset.las", aerial);
POINTNPR_KNN_BENCH(BM_Normals, "lidarhd_myria3d_870000_6618000_subset.las", aerial);
POINTNPR_KNN_BENCH(BM_GridKnn, "lion_takanawa.ply", lion);
POINTNPR_KNN_BENCH(BM_KdTreeKnn, "lion_takanawa.ply", lion);
POINTNPR_KNN_BENCH(BM_Normals, "lion_takanawa.ply", lion);

BENCHMARK_MAIN();
