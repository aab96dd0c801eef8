// Compiled once per SIMD target by Highway's foreach_target (this file
// includes itself); squared_distances() calls the best one for the CPU.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "geometry/neighbor_distances.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "geometry/neighbor_distances.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::geometry::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void SquaredDistances(const float* x, const float* y, const float* z, size_t n, const float* p,
                      const float* limit2, float* d2, size_t* below) {
  const hn::ScalableTag<float> d;
  const size_t lanes = hn::Lanes(d);
  const auto px = hn::Set(d, p[0]), py = hn::Set(d, p[1]), pz = hn::Set(d, p[2]);
  const auto l0 = hn::Set(d, limit2[0]), l1 = hn::Set(d, limit2[1]), l2 = hn::Set(d, limit2[2]);
  size_t j = 0;
  for (; j + lanes <= n; j += lanes) {
    const auto dx = hn::Sub(px, hn::LoadU(d, x + j)), dy = hn::Sub(py, hn::LoadU(d, y + j)),
               dz = hn::Sub(pz, hn::LoadU(d, z + j));
    const auto dist = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
    hn::StoreU(dist, d, d2 + j);
    below[0] += hn::CountTrue(d, hn::Lt(dist, l0));
    below[1] += hn::CountTrue(d, hn::Lt(dist, l1));
    below[2] += hn::CountTrue(d, hn::Lt(dist, l2));
  }
  for (; j < n; ++j) {  // the last few, in the same float operations
    const float dx = p[0] - x[j], dy = p[1] - y[j], dz = p[2] - z[j];
    d2[j] = dx * dx + dy * dy + dz * dz;
    for (int t = 0; t < 3; ++t) below[t] += d2[j] < limit2[t] ? 1 : 0;
  }
}

}  // namespace pointnpr::geometry::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pointnpr::geometry {
HWY_EXPORT(SquaredDistances);

void squared_distances(const float* x, const float* y, const float* z, size_t n, const std::array<float, 3>& p,
                       const std::array<float, 3>& limit2, float* d2, std::array<size_t, 3>& below) {
  below = {0, 0, 0};
  HWY_DYNAMIC_DISPATCH(SquaredDistances)(x, y, z, n, p.data(), limit2.data(), d2, below.data());
}
}  // namespace pointnpr::geometry
#endif
