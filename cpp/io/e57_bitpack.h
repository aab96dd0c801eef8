#pragma once
// E57 CompressedVector binary sections: the section header, the data, index
// and empty packets, and the bit-pack codec that every E57 writer uses
// (ASTM E2807 section 9). Each prototype field has its own bytestream; a
// data packet carries a piece of every stream, so the streams advance
// independently and a value may straddle two packets.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.h"
#include "io/e57_pages.h"

namespace pointnpr::e57 {

enum class FieldKind { Float32, Float64, Integer, ScaledInteger };

// One terminal of a CompressedVector's prototype and how its bytestream codes it.
struct FieldCodec {
  std::string name;  // path within the prototype ("cartesianX", "nor:normalX", "a/b")
  FieldKind kind = FieldKind::Float64;
  int64_t minimum = 0;  // integers: the stored value is value - minimum
  int64_t maximum = 0;
  double scale = 1.0;  // scaled integers: value * scale + offset
  double offset = 0.0;
  int bits = 64;  // bits per record in the stream (0: every value is `minimum`)
};

// Bits an integer field in [minimum, maximum] takes: ceil(log2(range + 1)).
int integer_bits(int64_t minimum, int64_t maximum);

// Decodes one bytestream into doubles, as packets hand it over in pieces.
class StreamDecoder {
 public:
  StreamDecoder(const FieldCodec& codec, double* out, uint64_t count);
  // Appends the next bytes of this stream and decodes every whole record in them.
  void feed(const uint8_t* bytes, size_t n);
  uint64_t decoded() const { return decoded_; }
  bool done() const { return decoded_ == count_; }

 private:
  void decode_available();
  FieldCodec codec_;
  double* out_;
  uint64_t count_;
  uint64_t decoded_ = 0;
  std::vector<uint8_t> pending_;  // undecoded bytes (then kPad zero bytes)
  size_t pending_bytes_ = 0;
  unsigned first_bit_ = 0;  // bit of pending_[0] where the next value starts
};

// Reads the CompressedVector section at `section_physical` holding
// `record_count` records of `fields`: one column of record_count doubles per
// field. Throws ReadError (bad section or packet header, counts the section
// cannot hold, streams that end early or do not match the prototype).
// `progress` (may be null) expects the section's bytes and advances by
// packet; cancelling it stops the decoding at the next packet (Cancelled).
std::vector<std::vector<double>> decode_compressed_vector(const PagedFile& file, uint64_t section_physical,
                                                          uint64_t record_count,
                                                          const std::vector<FieldCodec>& fields,
                                                          Progress* progress = nullptr);

}  // namespace pointnpr::e57
