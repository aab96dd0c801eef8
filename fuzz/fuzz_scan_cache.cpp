// libFuzzer target: the out-of-core scan cache's reader on arbitrary bytes:
// opening validates header and table, reading every chunk its checksum and
// layout ranks. A ReadError is the expected outcome; a chunk that passes
// must lie inside the bytes (ASan checks the reads).
#include <cstdlib>

#include "core/error.h"
#include "io/scan_cache.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const pointnpr::io::ScanCache cache("fuzz.pnprcache", data, size);
    uint64_t points = 0;
    for (size_t i = 0; i < cache.chunks().size(); ++i) {
      try {
        const pointnpr::io::ScanCacheChunkData d = cache.chunk(i);
        volatile uint8_t sink = 0;
        if (d.count > 0) sink = sink ^ d.positions[0] ^ d.layout_rank[4 * size_t(d.count) - 1];
        (void)sink;
      } catch (const pointnpr::ReadError&) {
      }
      points += cache.chunks()[i].count;
    }
    if (points != cache.size()) std::abort();  // open promised the table adds up
  } catch (const pointnpr::ReadError&) {
  }
  return 0;
}
