// The frame's point budget (render/point_budget.h): within the budget, one
// density for every chunk, and a larger budget only lengthens prefixes.
#include <gtest/gtest.h>

#include <random>

#include "render/point_budget.h"

namespace pointnpr {
namespace {

std::vector<BudgetChunk> random_chunks(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<uint32_t> count(0, 16384);
  std::uniform_real_distribution<double> area(1.0, 5e4);
  std::vector<BudgetChunk> chunks;
  for (int i = 0; i < n; ++i) chunks.push_back({count(rng), area(rng)});
  return chunks;
}

uint64_t total(const std::vector<BudgetChunk>& chunks) {
  uint64_t sum = 0;
  for (const BudgetChunk& c : chunks) sum += c.wanted;
  return sum;
}

TEST(PointBudget, NoBudgetOrABudgetOverTheFrameDrawsEveryPointWanted) {
  const auto chunks = random_chunks(200, 1);
  for (uint64_t budget : {uint64_t(0), total(chunks), total(chunks) + 1000}) {
    const BudgetPlan plan = plan_point_budget(chunks, budget);
    EXPECT_FALSE(plan.applied);
    ASSERT_EQ(plan.counts.size(), chunks.size());
    for (size_t i = 0; i < chunks.size(); ++i) EXPECT_EQ(plan.counts[i], chunks[i].wanted);
    EXPECT_EQ(plan.drawn, total(chunks));
  }
}

TEST(PointBudget, StaysWithinTheBudgetAndFillsIt) {
  const auto chunks = random_chunks(500, 2);
  for (uint64_t budget : {uint64_t(1), uint64_t(1000), uint64_t(250000), total(chunks) - 1}) {
    const BudgetPlan plan = plan_point_budget(chunks, budget);
    ASSERT_TRUE(plan.applied);
    uint64_t sum = 0;
    for (size_t i = 0; i < chunks.size(); ++i) {
      EXPECT_LE(plan.counts[i], chunks[i].wanted);
      sum += plan.counts[i];
    }
    EXPECT_EQ(sum, plan.drawn);
    EXPECT_LE(sum, budget);
    // Filled up to rounding: at most one point per chunk short.
    EXPECT_GE(sum + chunks.size(), std::min(budget, total(chunks)));
  }
}

TEST(PointBudget, OneDensityOnScreenForChunksNotExhausted) {
  const auto chunks = random_chunks(300, 3);
  const BudgetPlan plan = plan_point_budget(chunks, total(chunks) / 4);
  ASSERT_TRUE(plan.applied);
  ASSERT_GT(plan.level, 0.0);
  int cut = 0;
  for (size_t i = 0; i < chunks.size(); ++i) {
    if (plan.counts[i] == chunks[i].wanted) {
      // Whole chunks are those too sparse to reach the level.
      EXPECT_LE(double(chunks[i].wanted), plan.level * chunks[i].area + 0.5);
      continue;
    }
    ++cut;
    EXPECT_NEAR(double(plan.counts[i]), plan.level * chunks[i].area, 0.5 + 1e-9);
  }
  EXPECT_GT(cut, 0);
}

TEST(PointBudget, ALargerBudgetOnlyAddsPointsAtTheQueuesEnds) {
  const auto chunks = random_chunks(400, 4);
  BudgetPlan previous = plan_point_budget(chunks, 1);
  for (uint64_t budget = 1; budget < total(chunks); budget = budget * 3 / 2 + 7) {
    const BudgetPlan plan = plan_point_budget(chunks, budget);
    EXPECT_GE(plan.level, previous.level);
    for (size_t i = 0; i < chunks.size(); ++i) ASSERT_GE(plan.counts[i], previous.counts[i]) << "budget " << budget;
    previous = plan;
  }
}

TEST(PointBudget, EmptyFramesAndEmptyChunks) {
  EXPECT_EQ(plan_point_budget({}, 10).drawn, 0u);
  const std::vector<BudgetChunk> empty = {{0, 100.0}, {0, 5.0}};
  const BudgetPlan plan = plan_point_budget(empty, 1);
  EXPECT_FALSE(plan.applied);
  EXPECT_EQ(plan.counts, (std::vector<uint32_t>{0, 0}));
}

}  // namespace
}  // namespace pointnpr
