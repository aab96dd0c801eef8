#pragma once
// The frame's point budget: level of detail by the continuous resolution
// queue (seed 001 sections 6.3, 7.2) for every mark. When the visible chunks
// hold more points than the budget, each draws the first
// min(its mark's count, round(L x its projected area)) points of its queue
// order, with one density L (points per pixel of area) for the whole frame:
// the largest at which the frame stays within the budget. So the density of
// marks on screen is even across chunks near and far, and a larger budget
// only ever adds points at the ends of the chunks' queues (L never falls as
// the budget grows).
#include <cstdint>
#include <span>
#include <vector>

namespace pointnpr {

struct BudgetChunk {
  uint32_t wanted = 0;  // what the chunk's mark would draw without a budget
  double area = 0.0;    // projected area of its bounds, pixels (> 0)
};

struct BudgetPlan {
  bool applied = false;          // false: every chunk draws what it wanted
  double level = 0.0;            // L, points per pixel of projected area
  std::vector<uint32_t> counts;  // per chunk, <= wanted; sum <= budget
  uint64_t drawn = 0;
};

// `budget` 0 means no budget.
BudgetPlan plan_point_budget(std::span<const BudgetChunk> chunks, uint64_t budget);

}  // namespace pointnpr
