#pragma once
// Progress and cancellation of a long core call (geometry on millions of
// points), shared between the thread that runs it and one that watches it
// (Blender's UI, a Python thread). The caller opens a ProgressScope on the
// thread that makes the call; the call's functions pick the Progress up
// with current_progress() on that thread (and hand the pointer to their
// worker threads), so nothing in between has to pass it along. They count
// their work with advance() and stop at the next check() after cancel(),
// by throwing Cancelled; whatever they were computing is dropped, caches
// are left as they were.
#include <atomic>
#include <cstdint>
#include <string>

#include "core/error.h"

namespace pointnpr {

// The user (or the host) stopped a long call; not a failure.
class Cancelled : public Error {
 public:
  explicit Cancelled(const std::string& what = "cancelled") : Error(what) {}
};

class Progress {
 public:
  // Any thread.
  void cancel() noexcept { cancelled_.store(true, std::memory_order_relaxed); }
  bool cancelled() const noexcept { return cancelled_.load(std::memory_order_relaxed); }
  // Work done over work expected, in [0, 1]; 0 before the call has planned
  // its work, 1 once it has completed.
  double fraction() const noexcept;

  // The call: how much work it plans (in any unit, e.g. points per stage),
  // how much is done, and the cancellation point.
  void expect(uint64_t units) noexcept { expected_.fetch_add(units, std::memory_order_relaxed); }
  void advance(uint64_t units) noexcept { done_.fetch_add(units, std::memory_order_relaxed); }
  void check() const {
    if (cancelled()) throw Cancelled();
  }

 private:
  std::atomic<bool> cancelled_{false};
  std::atomic<uint64_t> expected_{0}, done_{0};
};

// The Progress of the innermost ProgressScope of the calling thread, or
// nullptr (no one watches: the helpers below do nothing).
Progress* current_progress() noexcept;

class ProgressScope {
 public:
  explicit ProgressScope(Progress* progress) noexcept;
  ~ProgressScope();
  ProgressScope(const ProgressScope&) = delete;
  ProgressScope& operator=(const ProgressScope&) = delete;

 private:
  Progress* previous_;
};

inline void check_cancelled(const Progress* p) {
  if (p) p->check();
}
inline void advance(Progress* p, uint64_t units) noexcept {
  if (p) p->advance(units);
}

}  // namespace pointnpr
