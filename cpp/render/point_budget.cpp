#include "render/point_budget.h"

#include <algorithm>
#include <cmath>

namespace pointnpr {
namespace {

uint32_t count_at(const BudgetChunk& c, double level) {
  const double n = std::floor(level * c.area + 0.5);
  return n >= double(c.wanted) ? c.wanted : uint32_t(std::max(n, 0.0));
}

uint64_t total_at(std::span<const BudgetChunk> chunks, double level) {
  uint64_t sum = 0;
  for (const BudgetChunk& c : chunks) sum += count_at(c, level);
  return sum;
}

}  // namespace

BudgetPlan plan_point_budget(std::span<const BudgetChunk> chunks, uint64_t budget) {
  BudgetPlan plan;
  uint64_t wanted = 0;
  double top = 0.0;  // at this level every chunk draws all it wanted
  for (const BudgetChunk& c : chunks) {
    wanted += c.wanted;
    if (c.area > 0.0) top = std::max(top, (double(c.wanted) + 1.0) / c.area);
  }
  plan.counts.reserve(chunks.size());
  if (budget == 0 || wanted <= budget) {
    for (const BudgetChunk& c : chunks) plan.counts.push_back(c.wanted);
    plan.drawn = wanted;
    return plan;
  }
  // Bisection over a fixed interval and a fixed number of steps: the same
  // level for the same chunks in every process, and for budgets b1 < b2 the
  // level found for b2 is never below b1's (each step's test is monotone).
  double lo = 0.0, hi = top;
  for (int step = 0; step < 64; ++step) {
    const double mid = 0.5 * (lo + hi);
    if (total_at(chunks, mid) <= budget)
      lo = mid;
    else
      hi = mid;
  }
  plan.applied = true;
  plan.level = lo;
  for (const BudgetChunk& c : chunks) {
    plan.counts.push_back(count_at(c, lo));
    plan.drawn += plan.counts.back();
  }
  return plan;
}

}  // namespace pointnpr
