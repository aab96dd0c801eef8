#pragma once
// Error types of the core. Every failure the host can provoke (bad input,
// missing GL, shader problems) becomes one of these, never a crash; the
// bindings translate them into Python exceptions.
#include <cstdint>
#include <stdexcept>
#include <string>

namespace pointnpr {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parameter names, types and ranges checked against the schema.
class ParameterError : public Error {
 public:
  using Error::Error;
};

// No context could be made, a shader failed, or GL reported an error.
class GLError : public Error {
 public:
  using Error::Error;
};

// A point cloud file could not be read. Carries the file and, where it
// applies, the byte offset at which the problem was found.
class ReadError : public Error {
 public:
  ReadError(const std::string& file, const std::string& reason, int64_t byte_offset = -1);
  const std::string& file() const { return file_; }
  const std::string& reason() const { return reason_; }
  int64_t byte_offset() const { return byte_offset_; }

 private:
  std::string file_;
  std::string reason_;
  int64_t byte_offset_;
};

}  // namespace pointnpr
