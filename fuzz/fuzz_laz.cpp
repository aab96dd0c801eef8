// libFuzzer target: the LAZ (LASzip) decoder through the LAS reader on
// arbitrary bytes, seeded with the LAZ test files (see fuzz_common.h).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pointnpr::fuzz::run(data, size, "fuzz.laz", pointnpr::read_las_memory);
}
