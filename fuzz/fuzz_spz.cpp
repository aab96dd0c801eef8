// libFuzzer target: the SPZ reader on arbitrary bytes (see fuzz_common.h).
// Raw bytes rarely make a gzip stream, so the seeds (tests/data/io/**.spz)
// and libFuzzer's mutations of them carry most of the reach.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pointnpr::fuzz::run(data, size, "fuzz.spz", pointnpr::read_spz_memory);
}
