// libFuzzer target: the E57 reader on arbitrary bytes (see fuzz_common.h).
// Page checksums are not checked: a mutated input would almost never pass
// them, and the layers behind them (XML, packets, bit-pack) are the target.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pointnpr::fuzz::run(data, size, "fuzz.e57", [](const uint8_t* d, size_t n, const std::string& name) {
    return pointnpr::read_e57_memory(d, n, name, false);
  });
}
