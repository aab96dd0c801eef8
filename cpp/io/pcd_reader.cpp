#include "core/error.h"
#include "io/readers.h"

namespace pointnpr {
PointData read_pcd(const std::string& path) { throw ReadError(path, "PCD files are not supported yet"); }
}  // namespace pointnpr
