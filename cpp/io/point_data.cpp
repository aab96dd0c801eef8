#include "io/point_data.h"

#include <cmath>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace pointnpr {

namespace io {
void advise_huge_pages(const void* p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  if (bytes < (size_t{4} << 20)) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}
}  // namespace io

size_t PointAttribute::num_points() const {
  size_t n = std::visit([](const auto& v) { return v.size(); }, values);
  return components > 0 ? n / static_cast<size_t>(components) : 0;
}

const PointAttribute* PointData::find(const std::string& name) const {
  for (const PointAttribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

PointAttribute* PointData::find(const std::string& name) {
  for (PointAttribute& a : attributes)
    if (a.name == name) return &a;
  return nullptr;
}

void PointData::remove(const std::string& name) {
  for (auto it = attributes.begin(); it != attributes.end(); ++it) {
    if (it->name == name) {
      attributes.erase(it);
      return;
    }
  }
}

size_t PointData::drop_nonfinite_points() {
  const size_t n = num_points();
  std::vector<uint8_t> keep(n);
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    const double* p = &positions[3 * i];
    keep[i] = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    kept += keep[i];
  }
  if (kept == n) return 0;
  auto compact = [&](auto& v, size_t comps) {
    size_t w = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!keep[i]) continue;
      for (size_t c = 0; c < comps; ++c) v[w * comps + c] = v[i * comps + c];
      ++w;
    }
    v.resize(w * comps);
    v.shrink_to_fit();
  };
  compact(positions, 3);
  for (PointAttribute& a : attributes)
    std::visit([&](auto& v) { compact(v, static_cast<size_t>(a.components)); }, a.values);
  metadata["dropped_nonfinite"] = static_cast<int64_t>(n - kept);
  return n - kept;
}

}  // namespace pointnpr
