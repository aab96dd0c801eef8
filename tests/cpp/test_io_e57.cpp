// E57's lowest layers: the pages' CRC-32C and the bit-pack codec, on bytes
// built here; the reader on pye57's test files (tests/python/test_io_e57.py
// compares every scan with pye57).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/e57_bitpack.h"
#include "io/e57_pages.h"
#include "io/readers.h"
#include "test_io_util.h"

namespace pointnpr {
namespace {

using e57::FieldCodec;
using e57::FieldKind;

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

TEST(IoE57, Crc32cMatchesTheCastagnoliCheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(e57::crc32c(reinterpret_cast<const uint8_t*>(check), 9), 0xE3069283u);
  // 32 zero bytes (RFC 3720's test vector): the slicing-by-8 path and the tail.
  const std::vector<uint8_t> zeros(32, 0);
  EXPECT_EQ(e57::crc32c(zeros.data(), zeros.size()), 0x8A9136AAu);
  std::vector<uint8_t> ones(32, 0xFF);
  EXPECT_EQ(e57::crc32c(ones.data(), ones.size()), 0x62A8AB43u);
}

TEST(IoE57, EveryPageOfARealFileHasItsCrc) {
  const std::vector<uint8_t> bytes = file_bytes(test_io::data_path("e57/pye57_pumpAVisualReferenceImage.e57"));
  ASSERT_EQ(bytes.size(), 4110336u);
  e57::PagedFile file("pump.e57", bytes.data(), bytes.size());
  EXPECT_NO_THROW(file.verify_checksums());
}

TEST(IoE57, ABadCrcNamesThePageAndItsOffset) {
  std::vector<uint8_t> bytes = file_bytes(test_io::data_path("e57/pye57_pumpAVisualReferenceImage.e57"));
  bytes[3 * 1024 + 100] ^= 0x10;  // a byte of page 3's content
  try {
    read_e57_scans_memory(bytes.data(), bytes.size(), "pump.e57");
    FAIL() << "no ReadError";
  } catch (const ReadError& e) {
    EXPECT_NE(e.reason().find("CRC-32C mismatch in page 3 (bytes 3072-4095)"), std::string::npos) << e.what();
    EXPECT_EQ(e.byte_offset(), 3 * 1024 + 1020);
  }
}

// Values packed as E57's bit-pack codec does: LSB first, one continuous stream.
std::vector<uint8_t> pack(const std::vector<uint64_t>& raw, int bits) {
  std::vector<uint8_t> out((raw.size() * static_cast<size_t>(bits) + 7) / 8, 0);
  uint64_t bit = 0;
  for (uint64_t v : raw)
    for (int b = 0; b < bits; ++b, ++bit)
      if ((v >> b) & 1) out[bit / 8] |= static_cast<uint8_t>(1u << (bit % 8));
  return out;
}

// Feeds `bytes` in pieces of random sizes (values straddle pieces, as they
// straddle data packets) and returns the decoded column.
std::vector<double> decode_in_pieces(const FieldCodec& codec, const std::vector<uint8_t>& bytes, size_t count,
                                     uint32_t seed) {
  e57::StreamDecoder decoder(codec, count);
  std::mt19937 rng(seed);
  size_t at = 0;
  while (at < bytes.size()) {
    const size_t n = std::min<size_t>(bytes.size() - at, std::uniform_int_distribution<size_t>(0, 37)(rng));
    decoder.feed(bytes.data() + at, n);
    at += n;
  }
  EXPECT_TRUE(decoder.done());
  const double* values = decoder.values(count);
  return std::vector<double>(values, values + count);
}

TEST(IoE57, BitPackDecodesIntegersOfEveryWidthAcrossPieces) {
  std::mt19937_64 rng(7);
  for (int bits = 1; bits <= 64; ++bits) {
    FieldCodec codec;
    codec.kind = FieldKind::Integer;
    // A range whose width is exactly `bits` bits, starting below zero.
    codec.minimum = bits == 64 ? INT64_MIN : -(int64_t{1} << (bits - 1));
    codec.maximum = bits == 64 ? INT64_MAX : (int64_t{1} << (bits - 1)) - 1;
    codec.bits = e57::integer_bits(codec.minimum, codec.maximum);
    ASSERT_EQ(codec.bits, bits);
    const uint64_t mask = bits == 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
    std::vector<uint64_t> raw(301);
    for (uint64_t& v : raw) v = rng() & mask;
    raw[0] = 0, raw[1] = mask;  // the range's ends
    const std::vector<double> out = decode_in_pieces(codec, pack(raw, bits), raw.size(), static_cast<uint32_t>(bits));
    for (size_t i = 0; i < raw.size(); ++i) {
      const int64_t value = static_cast<int64_t>(static_cast<uint64_t>(codec.minimum) + raw[i]);
      ASSERT_EQ(out[i], static_cast<double>(value)) << bits << " bits, value " << i;
    }
  }
}

TEST(IoE57, BitPackScalesScaledIntegers) {
  FieldCodec codec;
  codec.kind = FieldKind::ScaledInteger;
  codec.minimum = -1000, codec.maximum = 3000;  // 12 bits
  codec.scale = 0.001, codec.offset = 250.5;
  codec.bits = e57::integer_bits(codec.minimum, codec.maximum);
  ASSERT_EQ(codec.bits, 12);
  const std::vector<uint64_t> raw = {0, 4000, 1000, 1, 3999, 2500, 17};
  const std::vector<double> out = decode_in_pieces(codec, pack(raw, 12), raw.size(), 1);
  for (size_t i = 0; i < raw.size(); ++i)
    EXPECT_EQ(out[i], static_cast<double>(static_cast<int64_t>(raw[i]) - 1000) * 0.001 + 250.5);
}

TEST(IoE57, BitPackDecodesFloatsAndConstants) {
  const std::vector<float> singles = {1.5f, -0.0f, 3.4e38f, 1e-40f, -7.25f};
  std::vector<uint8_t> bytes(singles.size() * 4);
  std::memcpy(bytes.data(), singles.data(), bytes.size());
  FieldCodec f32;
  f32.kind = FieldKind::Float32, f32.bits = 32;
  const std::vector<double> a = decode_in_pieces(f32, bytes, singles.size(), 3);
  for (size_t i = 0; i < singles.size(); ++i) EXPECT_EQ(a[i], static_cast<double>(singles[i]));

  const std::vector<double> doubles = {M_PI, -1e300, 5e-324, 0.1};
  bytes.resize(doubles.size() * 8);
  std::memcpy(bytes.data(), doubles.data(), bytes.size());
  FieldCodec f64;
  f64.kind = FieldKind::Float64, f64.bits = 64;
  EXPECT_EQ(decode_in_pieces(f64, bytes, doubles.size(), 4), doubles);

  // minimum == maximum: no bytes at all, every record the minimum.
  FieldCodec constant;
  constant.kind = FieldKind::Integer, constant.minimum = constant.maximum = 42, constant.bits = 0;
  e57::StreamDecoder decoder(constant, 5);
  EXPECT_TRUE(decoder.done());
  const double* values = decoder.values(5);
  EXPECT_EQ(std::vector<double>(values, values + 5), std::vector<double>(5, 42.0));
}

TEST(IoE57, BitPackStopsAtTheRecordCount) {
  // Padding bits after the last record are not records.
  FieldCodec codec;
  codec.kind = FieldKind::Integer, codec.minimum = 0, codec.maximum = 6, codec.bits = 3;
  const std::vector<uint8_t> bytes = pack({1, 2, 3, 4, 5}, 3);  // 15 bits in 2 bytes
  e57::StreamDecoder decoder(codec, 4);
  decoder.feed(bytes.data(), bytes.size());
  EXPECT_EQ(decoder.decoded(), 4u);
  const double* values = decoder.values(4);
  EXPECT_EQ(std::vector<double>(values, values + 4), (std::vector<double>{1, 2, 3, 4}));
  // Dropped values are forgotten; the rest stay in order.
  decoder.drop(3);
  EXPECT_EQ(decoder.first(), 3u);
  EXPECT_EQ(decoder.values(1)[0], 4.0);
}

TEST(IoE57, ReadsPye57sTestFiles) {
  const std::vector<PointData> pump = read_e57_scans(test_io::data_path("e57/pye57_pumpAVisualReferenceImage.e57"));
  ASSERT_EQ(pump.size(), 1u);
  EXPECT_EQ(pump[0].num_points(), 155201u);
  EXPECT_EQ(std::get<std::string>(pump[0].metadata.at("scan_name")), "pumpA");
  EXPECT_EQ(std::get<std::string>(pump[0].metadata.at("images2d")),
            "pumpVisual (visualReferenceRepresentation, 3072x2304)");
  EXPECT_NEAR(pump[0].positions[0], 1.702286, 1e-6);
  ASSERT_NE(pump[0].get<int32_t>("row_index"), nullptr);
  EXPECT_EQ((*pump[0].get<int32_t>("row_index"))[0], 267);

  const std::vector<PointData> moved = read_e57_scans(test_io::data_path("e57/pye57_translationWithoutRotation.e57"));
  ASSERT_EQ(moved.size(), 1u);
  ASSERT_EQ(moved[0].num_points(), 4u);
  EXPECT_EQ(std::vector<double>(moved[0].positions.begin(), moved[0].positions.begin() + 3),
            (std::vector<double>{4, 5, 6}));
}

TEST(IoE57, TruncatedFileIsAReadError) {
  std::vector<uint8_t> bytes = file_bytes(test_io::data_path("e57/pye57_testWithNormals.e57"));
  bytes.resize(bytes.size() - 1024);
  try {
    read_e57_scans_memory(bytes.data(), bytes.size(), "cut.e57");
    FAIL() << "no ReadError";
  } catch (const ReadError& e) {
    EXPECT_NE(e.reason().find("(truncated)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pointnpr
