// Progress and cancellation of long geometry calls (core/progress.h): the
// fraction only grows and ends at 1, a cancel stops the call at its next
// check with Cancelled, and a cancelled call leaves the cache as it was.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <thread>

#include "core/progress.h"
#include "geometry/analysis.h"

using namespace pointnpr;
using namespace pointnpr::geometry;

namespace {

struct Cloud {
  std::vector<double> xyz;
  std::vector<uint32_t> colors;
};

// A wavy sheet with colour patches: every geometry call has work to do.
Cloud sheet(int n, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Cloud c;
  for (int i = 0; i < n; ++i) {
    const double x = 10.0 * u(rng), y = 10.0 * u(rng);
    c.xyz.insert(c.xyz.end(), {x, y, 0.3 * std::sin(x) * std::cos(y)});
    const uint32_t shade = (int(x) + int(y)) % 2 ? 200u : 60u;
    c.colors.push_back(shade | shade << 8 | 0x40u << 16 | 0xff000000u);
  }
  return c;
}

// Runs call() in a thread under a ProgressScope of `progress`, sampling the
// fraction from this thread until it ends; returns whether it was cancelled.
template <class F>
bool watch(Progress& progress, F call, std::vector<double>& fractions, double cancel_at = 2.0) {
  std::atomic<bool> finished{false}, cancelled{false};
  std::thread worker([&] {
    const ProgressScope scope(&progress);
    try {
      call();
    } catch (const Cancelled&) {
      cancelled = true;
    }
    finished = true;
  });
  while (!finished) {
    fractions.push_back(progress.fraction());
    if (fractions.back() >= cancel_at) progress.cancel();
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  worker.join();
  fractions.push_back(progress.fraction());
  return cancelled;
}

void expect_monotone(const std::vector<double>& f) {
  for (size_t i = 1; i < f.size(); ++i) ASSERT_GE(f[i], f[i - 1]);
}

}  // namespace

TEST(GeometryProgress, FractionGrowsToOneForEachLongCall) {
  const Cloud c = sheet(60000);
  {
    Analysis a(c.xyz, c.colors);
    Progress p;
    std::vector<double> f;
    EXPECT_FALSE(watch(p, [&] { a.region_growing_rgb({}); }, f));
    expect_monotone(f);
    EXPECT_DOUBLE_EQ(f.back(), 1.0);
  }
  {
    Analysis a(c.xyz);
    Progress p;
    std::vector<double> f;
    EXPECT_FALSE(watch(p, [&] { a.normals({16, Orientation::Consistent, {}}); }, f));
    expect_monotone(f);
    EXPECT_DOUBLE_EQ(f.back(), 1.0);
    // Cached now: a second call plans nothing and leaves a fresh Progress at 0.
    Progress again;
    const ProgressScope scope(&again);
    a.normals({16, Orientation::Consistent, {}});
    EXPECT_EQ(again.fraction(), 0.0);
  }
  for (auto call : {+[](Analysis& a) { a.connected_components(8, 5); },
                    +[](Analysis& a) { a.feature_degree(12, {}); },
                    +[](Analysis& a) { a.local_resolution(8); }, +[](Analysis& a) { a.inliers(10, 2.0f); },
                    +[](Analysis& a) { a.line_fit({}, 8); }}) {
    Analysis a(c.xyz, c.colors);
    Progress p;
    const ProgressScope scope(&p);
    call(a);
    EXPECT_DOUBLE_EQ(p.fraction(), 1.0);
  }
}

TEST(GeometryProgress, ACancelStopsTheCallAndLeavesTheCacheAsItWas) {
  const Cloud c = sheet(300000, 2);
  Analysis a(c.xyz, c.colors);
  Progress p;
  std::vector<double> f;
  // Cancelled as soon as any work is reported: most of it is still to do.
  EXPECT_TRUE(watch(p, [&] { a.region_growing_rgb({}); }, f, 1e-9));
  EXPECT_LT(f.back(), 0.9);
  for (const std::string& name : a.computed()) EXPECT_NE(name.rfind("knn:", 0), 0u) << name;

  // Cancelled before it starts: nothing is computed.
  Progress early;
  early.cancel();
  {
    const ProgressScope scope(&early);
    EXPECT_THROW(a.normals({16, Orientation::None, {}}), Cancelled);
    EXPECT_THROW(a.connected_components(8, 5), Cancelled);
  }
  // The same calls afterwards give what a fresh analysis gives.
  Analysis fresh(c.xyz, c.colors);
  EXPECT_EQ(a.region_growing_rgb({}).labels, fresh.region_growing_rgb({}).labels);
  EXPECT_EQ(*a.normals({16, Orientation::None, {}}), *fresh.normals({16, Orientation::None, {}}));
}
