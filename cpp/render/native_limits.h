#pragma once
// What the native (CPU) mark backends take from the render call, not from
// the process: tests lower the limits to reach, on a small scene, the paths
// a large one takes (several batches, cut bins, splat frames made per
// splat), and pick the scalar lanes to compare the SIMD ones with. Zero (or
// false) is the backend's own choice; production leaves them so.
#include <algorithm>
#include <cstdint>

namespace pointnpr {

struct NativeLimits {
  bool scalar_lanes = false;     // the scalar lanes even where the CPU has AVX2
  uint64_t kept_frames_max = 0;  // clouds of more points make their splat frames per splat
  uint64_t batch_splats = 0;     // splats set up and drawn a batch
  uint64_t max_bins = 0;         // screen bins before wider ones are cut

  // `limit` where it is set, within [1, fallback]; else `fallback`.
  static uint64_t lowered(uint64_t limit, uint64_t fallback) {
    return limit ? std::clamp<uint64_t>(limit, 1, fallback) : fallback;
  }
};

}  // namespace pointnpr
