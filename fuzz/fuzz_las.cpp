// libFuzzer target: the LAS reader on arbitrary bytes (see fuzz_common.h).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pointnpr::fuzz::run(data, size, "fuzz.las", pointnpr::read_las_memory);
}
