#include "marks/stipples/native_parts.h"

#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace pointnpr::stipples_native {

void spread_step(glm::ivec2 size, float step, const uint32_t* in, uint32_t* out) {
  const int W = size.x, H = size.y;
  tbb::parallel_for(tbb::blocked_range<int>(0, H, kRowGrain), [&](const tbb::blocked_range<int>& rows) {
    std::vector<uint32_t> column(static_cast<size_t>(W));
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const uint32_t* a = in + size_t(std::max(y - 1, 0)) * size_t(W);
      const uint32_t* b = in + size_t(y) * size_t(W);
      const uint32_t* c = in + size_t(std::min(y + 1, H - 1)) * size_t(W);
      // Positive depths (and +inf) order as their bits.
      for (int x = 0; x < W; ++x) column[size_t(x)] = std::min(std::min(a[x], b[x]), c[x]);
      uint32_t* o = out + size_t(y) * size_t(W);
      for (int x = 0; x < W; ++x) {
        const uint32_t m = std::min(std::min(column[size_t(std::max(x - 1, 0))], column[size_t(x)]),
                                    column[size_t(std::min(x + 1, W - 1))]);
        o[x] = m == kInfBits ? b[x] : std::min(b[x], bits(from_bits(m) + step));
      }
    }
  });
}

void box_min(glm::ivec2 size, const uint32_t* in, uint32_t* out, int r) {
  const int W = size.x, H = size.y;
  tbb::parallel_for(tbb::blocked_range<int>(0, H, kRowGrain), [&](const tbb::blocked_range<int>& rows) {
    std::vector<uint32_t> column(static_cast<size_t>(W));
    for (int y = rows.begin(); y < rows.end(); ++y) {
      const int y0 = std::max(y - r, 0), y1 = std::min(y + r, H - 1);
      std::memcpy(column.data(), in + size_t(y0) * size_t(W), size_t(W) * 4);
      for (int q = y0 + 1; q <= y1; ++q) {
        const uint32_t* line = in + size_t(q) * size_t(W);
        for (int x = 0; x < W; ++x) column[size_t(x)] = std::min(column[size_t(x)], line[x]);
      }
      uint32_t* o = out + size_t(y) * size_t(W);
      for (int x = 0; x < W; ++x) {
        uint32_t m = kInfBits;
        const int x0 = std::max(x - r, 0), x1 = std::min(x + r, W - 1);
        for (int q = x0; q <= x1; ++q) m = std::min(m, column[size_t(q)]);
        o[x] = m;
      }
    }
  });
}

}  // namespace pointnpr::stipples_native
