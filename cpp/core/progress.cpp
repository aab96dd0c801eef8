#include "core/progress.h"

#include <algorithm>

namespace pointnpr {

namespace {
thread_local Progress* current = nullptr;
}

double Progress::fraction() const noexcept {
  const uint64_t expected = expected_.load(std::memory_order_relaxed);
  if (expected == 0) return 0.0;
  return std::min(1.0, double(done_.load(std::memory_order_relaxed)) / double(expected));
}

Progress* current_progress() noexcept { return current; }

ProgressScope::ProgressScope(Progress* progress) noexcept : previous_(current) { current = progress; }
ProgressScope::~ProgressScope() { current = previous_; }

}  // namespace pointnpr
