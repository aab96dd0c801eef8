#include "io/e57_bitpack.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include "core/error.h"
#include "io/mapped_file.h"
#include "io/point_data.h"

namespace pointnpr::e57 {

namespace {

// Zero bytes kept after the pending data: every value is read with one or
// two unaligned 8-byte loads that may reach past its last byte.
constexpr size_t kPad = 16;
constexpr size_t kSectionHeaderSize = 32;
constexpr uint8_t kCompressedVectorSection = 1;
constexpr uint8_t kIndexPacket = 0;
constexpr uint8_t kDataPacket = 1;
constexpr uint8_t kEmptyPacket = 2;
constexpr size_t kDataPacketHeaderSize = 6;

inline uint64_t bits_at(const uint8_t* p, uint64_t bit, int bits) {
  const uint8_t* b = p + (bit >> 3);
  const unsigned shift = static_cast<unsigned>(bit & 7);
  uint64_t v = io::load_le<uint64_t>(b) >> shift;
  if (shift + static_cast<unsigned>(bits) > 64) v |= static_cast<uint64_t>(b[8]) << (64 - shift);
  return bits == 64 ? v : v & ((uint64_t{1} << bits) - 1);
}

}  // namespace

int integer_bits(int64_t minimum, int64_t maximum) {
  const uint64_t range = static_cast<uint64_t>(maximum) - static_cast<uint64_t>(minimum);
  return static_cast<int>(std::bit_width(range));
}

StreamDecoder::StreamDecoder(const FieldCodec& codec, uint64_t count) : codec_(codec), count_(count) {
  // A constant field takes no bytes: every record is the minimum.
  if (codec_.bits == 0) decoded_ = count_;
  pending_.assign(kPad, 0);
}

const double* StreamDecoder::values(size_t n) {
  if (codec_.bits == 0) {
    const double v = codec_.kind == FieldKind::ScaledInteger
                         ? static_cast<double>(codec_.minimum) * codec_.scale + codec_.offset
                         : static_cast<double>(codec_.minimum);
    values_.assign(n, v);
  }
  return values_.data();
}

void StreamDecoder::drop(size_t n) {
  first_ += n;
  if (codec_.bits == 0) return;
  values_.erase(values_.begin(), values_.begin() + static_cast<std::ptrdiff_t>(n));
}

void StreamDecoder::feed(const uint8_t* bytes, size_t n) {
  if (done() || n == 0) return;
  pending_.resize(pending_bytes_ + n + kPad);
  std::memcpy(pending_.data() + pending_bytes_, bytes, n);
  std::memset(pending_.data() + pending_bytes_ + n, 0, kPad);
  pending_bytes_ += n;
  decode_available();
}

void StreamDecoder::decode_available() {
  const uint64_t bits = static_cast<uint64_t>(codec_.bits);
  const uint64_t available_bits = pending_bytes_ * 8 - first_bit_;
  const uint64_t records = std::min<uint64_t>(available_bits / bits, count_ - decoded_);
  const uint8_t* p = pending_.data();
  const size_t kept = values_.size();
  values_.resize(kept + static_cast<size_t>(records));
  double* out = values_.data() + kept;
  uint64_t bit = first_bit_;
  switch (codec_.kind) {
    case FieldKind::Float32:
      for (uint64_t i = 0; i < records; ++i, bit += 32) {
        const uint32_t raw = static_cast<uint32_t>(bits_at(p, bit, 32));
        out[i] = static_cast<double>(std::bit_cast<float>(raw));
      }
      break;
    case FieldKind::Float64:
      for (uint64_t i = 0; i < records; ++i, bit += 64) out[i] = std::bit_cast<double>(bits_at(p, bit, 64));
      break;
    case FieldKind::Integer: {
      const uint64_t min = static_cast<uint64_t>(codec_.minimum);
      const int b = codec_.bits;
      for (uint64_t i = 0; i < records; ++i, bit += bits)
        out[i] = static_cast<double>(static_cast<int64_t>(min + bits_at(p, bit, b)));
      break;
    }
    case FieldKind::ScaledInteger: {
      const uint64_t min = static_cast<uint64_t>(codec_.minimum);
      const int b = codec_.bits;
      const double scale = codec_.scale, offset = codec_.offset;
      for (uint64_t i = 0; i < records; ++i, bit += bits)
        out[i] = static_cast<double>(static_cast<int64_t>(min + bits_at(p, bit, b))) * scale + offset;
      break;
    }
  }
  decoded_ += records;
  // Keep the bytes from the one holding the next unread bit on.
  const size_t consumed = static_cast<size_t>(bit >> 3);
  first_bit_ = static_cast<unsigned>(bit & 7);
  pending_bytes_ -= consumed;
  std::memmove(pending_.data(), pending_.data() + consumed, pending_bytes_ + kPad);
  pending_.resize(pending_bytes_ + kPad);
}

namespace {

// Where a CompressedVector's section and its packets lie (logical offsets).
struct Section {
  uint64_t start = 0, end = 0;
  uint64_t data_physical = 0;
};

Section parse_section(const PagedFile& file, uint64_t section_physical, uint64_t record_count,
                      const std::vector<FieldCodec>& fields) {
  const int64_t at = static_cast<int64_t>(section_physical);
  const uint64_t start = file.to_logical(section_physical);
  uint8_t header[kSectionHeaderSize];
  file.copy(start, kSectionHeaderSize, header);
  if (header[0] != kCompressedVectorSection)
    file.fail("the binary section of a CompressedVector has section id " + std::to_string(header[0]) +
                  " (expected 1)", at);
  const uint64_t length = io::load_le<uint64_t>(header + 8);
  const uint64_t data_physical = io::load_le<uint64_t>(header + 16);
  if (length < kSectionHeaderSize || length > file.logical_size() - start)
    file.fail("CompressedVector section length " + std::to_string(length) + " does not fit in the file", at + 8);
  const uint64_t end = start + length;
  uint64_t total_bits = 0;
  for (const FieldCodec& f : fields) total_bits += static_cast<uint64_t>(f.bits);
  // Every record takes total_bits of the section's bytes. Constant fields
  // take none: records of constants alone are bounded by one per byte, so a
  // small file cannot ask for an unbounded allocation.
  const uint64_t max_records = total_bits == 0 ? length : length * 8 / total_bits;
  if (record_count > max_records)
    file.fail("recordCount " + std::to_string(record_count) + " is more than the " + std::to_string(length) +
                  "-byte section can hold (" + std::to_string(max_records) + " records of " +
                  std::to_string(total_bits) + " bits)", at);

  return {start, end, data_physical};
}

}  // namespace

void check_compressed_vector(const PagedFile& file, uint64_t section_physical, uint64_t record_count,
                             const std::vector<FieldCodec>& fields) {
  parse_section(file, section_physical, record_count, fields);
}

void decode_compressed_vector(const PagedFile& file, uint64_t section_physical, uint64_t record_count,
                              const std::vector<FieldCodec>& fields, const RowBlockSink& sink, Progress* progress,
                              size_t block_rows) {
  const Section section = parse_section(file, section_physical, record_count, fields);
  const int64_t at = static_cast<int64_t>(section_physical);
  const uint64_t start = section.start, end = section.end, data_physical = section.data_physical;

  std::vector<StreamDecoder> streams;
  streams.reserve(fields.size());
  for (const FieldCodec& f : fields) streams.emplace_back(f, record_count);
  auto all_done = [&] {
    return std::all_of(streams.begin(), streams.end(), [](const StreamDecoder& s) { return s.done(); });
  };
  // Hands over the records every stream has decoded, in blocks; `all`: the
  // last, partial block too.
  uint64_t emitted = 0;
  std::vector<const double*> columns(fields.size());
  auto emit = [&](bool all) {
    uint64_t complete = record_count;
    for (const StreamDecoder& s : streams) complete = std::min(complete, s.decoded());
    while (complete - emitted >= block_rows || (all && complete > emitted)) {
      const size_t n = static_cast<size_t>(std::min<uint64_t>(complete - emitted, block_rows));
      for (size_t f = 0; f < streams.size(); ++f) columns[f] = streams[f].values(n);
      sink(emitted, n, columns);
      for (StreamDecoder& s : streams) s.drop(n);
      emitted += n;
    }
  };
  if (record_count == 0) return;
  if (all_done()) return emit(true);

  uint64_t pos = file.to_logical(data_physical);
  if (pos < start + kSectionHeaderSize || pos >= end)
    file.fail("CompressedVector data offset " + std::to_string(data_physical) + " lies outside its section",
              at + 16);
  std::vector<uint8_t> packet(65536);
  if (progress) progress->expect(end - pos);
  while (pos < end && !all_done()) {
    check_cancelled(progress);
    const int64_t packet_at = static_cast<int64_t>(PagedFile::to_physical(pos));
    if (end - pos < 4) file.fail("a packet header runs past the end of its CompressedVector section", packet_at);
    file.copy(pos, 4, packet.data());
    const uint8_t type = packet[0];
    const size_t packet_length = size_t{io::load_le<uint16_t>(packet.data() + 2)} + 1;
    if (packet_length > end - pos)
      file.fail("a packet of " + std::to_string(packet_length) + " bytes runs past the end of its section",
                packet_at);
    if (type == kDataPacket) {
      file.copy(pos, packet_length, packet.data());
      if (packet_length < kDataPacketHeaderSize) file.fail("a data packet is too short for its header", packet_at);
      const size_t count = io::load_le<uint16_t>(packet.data() + 4);
      if (count != fields.size())
        file.fail("a data packet carries " + std::to_string(count) + " bytestreams but the prototype has " +
                      std::to_string(fields.size()) + " fields",
                  packet_at + 4);
      size_t offset = kDataPacketHeaderSize + 2 * count;
      if (offset > packet_length) file.fail("a data packet's bytestream lengths overrun the packet", packet_at);
      for (size_t s = 0; s < count; ++s) {
        const size_t n = io::load_le<uint16_t>(packet.data() + kDataPacketHeaderSize + 2 * s);
        if (n > packet_length - offset)
          file.fail("bytestream " + std::to_string(s) + " (" + fields[s].name + ") overruns its data packet",
                    packet_at);
        streams[s].feed(packet.data() + offset, n);
        offset += n;
      }
      emit(false);
    } else if (type != kIndexPacket && type != kEmptyPacket) {
      file.fail("unknown packet type " + std::to_string(type) + " in a CompressedVector section", packet_at);
    }
    pos += packet_length;
    advance(progress, packet_length);
  }
  if (pos < end) advance(progress, end - pos);  // all records read before the section's end
  for (size_t s = 0; s < streams.size(); ++s)
    if (!streams[s].done())
      file.fail("the data of field " + fields[s].name + " ends after " + std::to_string(streams[s].decoded()) +
                    " of " + std::to_string(record_count) + " records (the prototype does not match the data)",
                at);
  emit(true);
}

}  // namespace pointnpr::e57
