#pragma once
// E57 CompressedVector binary sections: the section header, the data, index
// and empty packets, and the bit-pack codec that every E57 writer uses
// (ASTM E2807 section 9). Each prototype field has its own bytestream; a
// data packet carries a piece of every stream, so the streams advance
// independently and a value may straddle two packets.
#include <cstddef>
#include <cstdint>
#include <functional>
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

// Decodes one bytestream of `count` records into doubles, as packets hand
// it over in pieces. The values decoded and not yet dropped are kept: record
// first() + i is values()[i].
class StreamDecoder {
 public:
  StreamDecoder(const FieldCodec& codec, uint64_t count);
  // Appends the next bytes of this stream and decodes every whole record in them.
  void feed(const uint8_t* bytes, size_t n);
  uint64_t decoded() const { return decoded_; }
  bool done() const { return decoded_ == count_; }
  uint64_t first() const { return first_; }
  // The values of records [first(), first() + n), n <= decoded() - first().
  const double* values(size_t n);
  // Forgets the values of the first n records kept.
  void drop(size_t n);

 private:
  void decode_available();
  FieldCodec codec_;
  uint64_t count_;
  uint64_t decoded_ = 0;
  uint64_t first_ = 0;
  std::vector<double> values_;  // records [first_, decoded_); a constant field: n copies on demand
  std::vector<uint8_t> pending_;  // undecoded bytes (then kPad zero bytes)
  size_t pending_bytes_ = 0;
  unsigned first_bit_ = 0;  // bit of pending_[0] where the next value starts
};

// Checks the section header of a CompressedVector and that it can hold
// `record_count` records of `fields` (before the caller allocates for them);
// throws ReadError. decode_compressed_vector checks the same.
void check_compressed_vector(const PagedFile& file, uint64_t section_physical, uint64_t record_count,
                             const std::vector<FieldCodec>& fields);

// Records [first, first + count) of every field, complete: columns[f][i]
// is field f of record first + i, valid during the call.
using RowBlockSink = std::function<void(uint64_t first, size_t count, const std::vector<const double*>& columns)>;

// Reads the CompressedVector section at `section_physical` holding
// `record_count` records of `fields`, handing them to `sink` in file order,
// in blocks of up to `block_rows` records once every field has them: only
// what one stream has decoded ahead of the others is held. Throws
// ReadError (bad section or packet header, counts the section cannot hold,
// streams that end early or do not match the prototype). `progress` (may
// be null) expects the section's bytes and advances by packet; cancelling
// it stops the decoding at the next packet (Cancelled).
void decode_compressed_vector(const PagedFile& file, uint64_t section_physical, uint64_t record_count,
                              const std::vector<FieldCodec>& fields, const RowBlockSink& sink,
                              Progress* progress = nullptr, size_t block_rows = size_t{1} << 16);

}  // namespace pointnpr::e57
