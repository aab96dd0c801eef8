// libFuzzer target: the TEXT reader on arbitrary bytes (see fuzz_common.h).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pointnpr::fuzz::run(data, size, "fuzz.pts", pointnpr::read_text_memory);
}
