#include "core/error.h"

namespace pointnpr {

namespace {
std::string format_read_error(const std::string& file, const std::string& reason, int64_t offset) {
  std::string msg = file + ": " + reason;
  if (offset >= 0) msg += " (at byte " + std::to_string(offset) + ")";
  return msg;
}
}  // namespace

ReadError::ReadError(const std::string& file, const std::string& reason, int64_t byte_offset)
    : Error(format_read_error(file, reason, byte_offset)),
      file_(file),
      reason_(reason),
      byte_offset_(byte_offset) {}

}  // namespace pointnpr
