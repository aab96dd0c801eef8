#pragma once
// LASzip (LAZ) point data: the "laszip encoded" VLR and the decompression of
// the point records into uncompressed LAS records, which the LAS reader then
// turns into columns exactly as it does for a .las file.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace pointnpr::laz {

// A problem with the file; `offset` is the byte it concerns (-1: none).
class FormatError : public std::runtime_error {
 public:
  FormatError(const std::string& what, int64_t at)
      : std::runtime_error(what), offset(at) {}
  int64_t offset;
};

enum ItemType : uint16_t {
  kByte = 0, kPoint10 = 6, kGpsTime11 = 7, kRgb12 = 8, kWavePacket13 = 9,
  kPoint14 = 10, kRgb14 = 11, kRgbNir14 = 12, kWavePacket14 = 13, kByte14 = 14,
};

struct Item {
  uint16_t type = 0, size = 0, version = 0;
};

// Payload of the "laszip encoded" VLR (record 22204).
struct LaszipVlr {
  uint16_t compressor = 0;  // 1 point-wise, 2 point-wise chunked, 3 layered chunked
  uint16_t coder = 0;       // 0: arithmetic
  uint8_t version_major = 0, version_minor = 0;
  uint16_t revision = 0;
  uint32_t chunk_size = 0;  // points per chunk; 0xFFFFFFFF: variable (in the chunk table)
  std::vector<Item> items;
};

// Throws FormatError naming what is wrong or unsupported.
LaszipVlr parse_laszip_vlr(const uint8_t* payload, uint64_t len, int64_t at);
// Checks that the items are known, supported and add up to the point record.
void check_items(const LaszipVlr& vlr, int point_format, size_t record_length);

// Decodes one chunk into uncompressed records. One per thread: the models
// are allocated once and reset per chunk.
class ChunkDecoder {
 public:
  virtual ~ChunkDecoder() = default;
  // Decodes the chunk stored in [begin, end). `points` is the count the
  // chunk table or chunk size implies (0: unknown, the chunk's own count is
  // used, up to `max_points`). Writes the records to `out` (room for
  // max_points records) and returns the number decoded; `*consumed` is set
  // to the end of the chunk's bytes. `exact_end`: `end` is the chunk's end
  // (from the chunk table), which its data must reach exactly. Throws
  // FormatError on corrupt data.
  virtual uint64_t decode(const uint8_t* begin, const uint8_t* end, uint64_t points,
                          uint64_t max_points, uint8_t* out, const uint8_t** consumed,
                          bool exact_end) = 0;
  // Whether a chunk knows its own point count and byte size (layered).
  virtual bool self_delimiting() const = 0;
};

std::unique_ptr<ChunkDecoder> make_pointwise_decoder(const LaszipVlr& vlr, size_t record_length);
std::unique_ptr<ChunkDecoder> make_layered_decoder(const LaszipVlr& vlr, size_t record_length);

// Receives decoded records [first, first + count) of the file; called from
// several threads at once (for different ranges) while chunks decode.
using ChunkSink = std::function<void(uint64_t first, const uint8_t* records, uint64_t count)>;

// Decompresses `count` records of `record_length` bytes and hands them to
// `sink` chunk by chunk. `file` is the whole file; the point data starts at
// `point_offset` and the compressed bytes end at or before `data_end` (the
// first EVLR or the file's end). Reports progress per chunk to the calling
// thread's Progress (if any) and stops at its cancel (Cancelled). Every
// count, size and offset is checked before use: FormatError otherwise.
// `ready` is called once the counts have been checked against the chunk
// table and the file, before the first record: the moment to allocate.
void decompress(const uint8_t* file, size_t file_size, uint64_t point_offset, uint64_t data_end,
                uint64_t count, size_t record_length, const LaszipVlr& vlr,
                const std::function<void()>& ready, const ChunkSink& sink);
// The same into one buffer of count * record_length bytes.
std::vector<uint8_t> decompress(const uint8_t* file, size_t file_size, uint64_t point_offset,
                                uint64_t data_end, uint64_t count, size_t record_length,
                                const LaszipVlr& vlr);

}  // namespace pointnpr::laz
