#include "core/error.h"
#include "io/readers.h"

namespace pointnpr {
PointData read_text(const std::string& path) { throw ReadError(path, "text point files are not supported yet"); }
}  // namespace pointnpr
