// libFuzzer target for the writers: whatever the PLY reader accepts (any
// property types and names, the richest input) is written as PLY and as LAS;
// the writer may refuse it (pointnpr::Error), but what it writes must read
// back with the same point count and positions: bit for bit from PLY,
// within half the chosen scale from LAS.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>
#include <vector>

#include "fuzz_common.h"

namespace {

const std::string& scratch_dir() {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/pointnpr_fuzz_roundtrip_XXXXXX";
    const char* d = ::mkdtemp(tmpl);
    if (!d) std::abort();
    return std::string(d);
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pointnpr;
  PointData d;
  try {
    d = read_ply_memory(data, size, "fuzz.ply");
  } catch (const ReadError&) {
    return 0;
  }
  fuzz::check(d);
  for (const char* ext : {".ply", ".las"}) {
    const std::string path = scratch_dir() + "/roundtrip" + ext;
    try {
      write_point_cloud(path, d);
    } catch (const ReadError&) {
      std::abort();  // writers never raise read errors
    } catch (const Error&) {
      continue;  // refused (a value the format cannot hold): fine
    }
    PointData r = read_point_cloud(path);  // a written file must read back
    fuzz::check(r);
    std::remove(path.c_str());
    if (r.num_points() != d.num_points()) std::abort();
    if (ext[1] == 'p') {
      if (r.positions != d.positions) std::abort();
    } else {
      const auto& scale = std::get<std::vector<double>>(r.metadata.at("scale"));
      const auto& offset = std::get<std::vector<double>>(r.metadata.at("offset"));
      for (size_t i = 0; i < d.positions.size(); ++i) {
        const double err = std::fabs(r.positions[i] - d.positions[i]);
        // Half a step (a tie rounds either way) plus the rounding of
        // (p - offset) / scale and k * scale + offset in doubles.
        const double tol = scale[i % 3] * 0.5 +
                           (std::fabs(d.positions[i]) + std::fabs(offset[i % 3])) * 1e-14;
        if (!(err <= tol)) std::abort();
      }
    }
  }
  return 0;
}
