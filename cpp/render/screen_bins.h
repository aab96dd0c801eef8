#pragma once
// Screen bins for the native paths that blend in a fixed order: items
// (splats, strokes) with a screen rectangle are binned into square tiles
// of the clip in item order, and each tile visits its items in that order
// on one thread, so per-pixel sums come out the same whatever the thread
// count or timing (the GL's blending order, primitive after primitive).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "render/filter.h"  // Rect

namespace pointnpr {

// `bounds(i, lo, hi)` gives item i's local pixels [lo, hi) (false: none);
// `visit(area, list, count)` draws the items list[0, count) (item indices,
// ascending) over the tile `area` of the clip. Bins of `side` pixels (a
// power of two), doubled while there would be more than `max_bins` of them.
template <class Bounds, class Visit>
void for_each_bin_in_order(size_t items, const Rect& clip, Bounds&& bounds, Visit&& visit, int side = 32,
                           size_t max_bins = 16384) {
  if (items == 0 || clip.empty()) return;
  if (!std::has_single_bit(unsigned(side))) throw Error("screen bins: side not a power of two");
  const glm::ivec2 size = clip.size();
  while (size_t((size.x + side - 1) / side) * size_t((size.y + side - 1) / side) > max_bins) side *= 2;
  const int shift = std::countr_zero(unsigned(side));  // (a bin by shifts: two per item and pass, no division)
  const int bins_x = (size.x + side - 1) / side, bins_y = (size.y + side - 1) / side;
  const size_t bins = size_t(bins_x) * size_t(bins_y);
  const size_t blocks = std::clamp<size_t>(items / 2048, 1, 128);
  const size_t per_block = (items + blocks - 1) / blocks;
  auto for_block = [&](size_t b, auto&& add) {
    const size_t end = std::min(items, (b + 1) * per_block);
    for (size_t i = b * per_block; i < end; ++i) {
      glm::ivec2 lo, hi;
      if (!bounds(i, lo, hi)) continue;
      lo = glm::max(lo, clip.min);
      hi = glm::min(hi, clip.max);
      if (lo.x >= hi.x || lo.y >= hi.y) continue;
      const glm::ivec2 b0 = (lo - clip.min) >> shift, b1 = (hi - 1 - clip.min) >> shift;
      for (int by = b0.y; by <= b1.y; ++by)
        for (int bx = b0.x; bx <= b1.x; ++bx) add(i, size_t(by) * size_t(bins_x) + size_t(bx));
    }
  };
  std::vector<uint32_t> counts(blocks * bins, 0);
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    uint32_t* c = &counts[b * bins];
    for_block(b, [c](size_t, size_t bin) { ++c[bin]; });
  });
  // Offsets bin major, block minor: each bin's list is in item order.
  std::vector<size_t> start(bins + 1, 0), offsets(blocks * bins);
  size_t total = 0;
  for (size_t bin = 0; bin < bins; ++bin) {
    start[bin] = total;
    for (size_t b = 0; b < blocks; ++b) {
      offsets[b * bins + bin] = total;
      total += counts[b * bins + bin];
    }
  }
  start[bins] = total;
  std::vector<uint32_t> list(total);
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t* o = &offsets[b * bins];
    for_block(b, [&](size_t i, size_t bin) { list[o[bin]++] = uint32_t(i); });
  });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, bins, 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t bin = r.begin(); bin < r.end(); ++bin) {
      const glm::ivec2 b(int(bin % size_t(bins_x)), int(bin / size_t(bins_x)));
      const Rect area{clip.min + b * side, glm::min(clip.min + (b + 1) * side, clip.max)};
      visit(area, list.data() + start[bin], start[bin + 1] - start[bin]);
    }
  });
}

}  // namespace pointnpr
