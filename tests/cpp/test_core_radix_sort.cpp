// core/radix_sort.h against std::stable_sort on the high words.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/radix_sort.h"

namespace pointnpr {
namespace {

std::vector<uint64_t> expected(std::vector<uint64_t> keys) {
  std::stable_sort(keys.begin(), keys.end(), [](uint64_t a, uint64_t b) { return a >> 32 < b >> 32; });
  return keys;
}

// Keys of `n` high words drawn from `high` (the low words: a running index,
// as the bins build them, or noise that must keep its order among ties).
std::vector<uint64_t> keys_of(size_t n, std::mt19937& rng, auto&& high, bool indexed) {
  std::vector<uint64_t> keys(n);
  for (size_t i = 0; i < n; ++i) keys[i] = uint64_t(high(rng)) << 32 | (indexed ? i : rng());
  return keys;
}

TEST(RadixSort, SortsByTheHighWordsStablyAsStdStableSort) {
  std::mt19937 rng(7);
  std::vector<uint64_t> scratch;
  for (const size_t n : {0u, 1u, 255u, 256u, 257u, 4000u, 100000u}) {
    for (const bool indexed : {true, false}) {
      std::uniform_int_distribution<uint32_t> any;
      std::uniform_int_distribution<uint32_t> few(0, 9);  // many ties
      std::uniform_int_distribution<uint32_t> one_byte(0x40a00000u, 0x40a000ffu);  // three bytes shared: passes skipped
      auto depths = [](std::mt19937& g) {  // positive floats' bits, as the bins' nearest depths
        const float d = std::uniform_real_distribution<float>(0.1f, 100.0f)(g);
        uint32_t bits;
        std::memcpy(&bits, &d, 4);
        return bits;
      };
      for (int kind = 0; kind < 4; ++kind) {
        std::vector<uint64_t> keys = kind == 0   ? keys_of(n, rng, any, indexed)
                                     : kind == 1 ? keys_of(n, rng, few, indexed)
                                     : kind == 2 ? keys_of(n, rng, one_byte, indexed)
                                                 : keys_of(n, rng, depths, indexed);
        const std::vector<uint64_t> want = expected(keys);
        stable_sort_by_high_words(keys, scratch);
        EXPECT_EQ(keys, want) << "n " << n << " kind " << kind << " indexed " << indexed;
        if (indexed) {  // unique keys: std::sort's order too
          std::vector<uint64_t> sorted = want;
          std::sort(sorted.begin(), sorted.end());
          EXPECT_EQ(keys, sorted);
        }
      }
    }
  }
}

TEST(RadixSort, AllKeysEqualInTheirHighWordsKeepTheirOrder) {
  std::vector<uint64_t> keys(1000), scratch;
  for (size_t i = 0; i < keys.size(); ++i) keys[i] = uint64_t(0x3f800000u) << 32 | (999 - i);
  const std::vector<uint64_t> before = keys;
  stable_sort_by_high_words(keys, scratch);
  EXPECT_EQ(keys, before);
}

}  // namespace
}  // namespace pointnpr
