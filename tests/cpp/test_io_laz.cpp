// LAZ (LASzip) decoding: the decompressed records equal the uncompressed
// twin byte for byte (every field, flags included), every layout of the test
// files reads, and corrupt copies raise ReadError (these also run under
// ASan + UBSan: scripts/sanitize_tests.sh). Field-by-field agreement with
// laspy + lazrs for every file is tests/python/test_io_laz.py.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/laz_reader.h"
#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::data_path;

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

template <class T>
T at(const std::string& b, size_t off) {
  T v;
  std::memcpy(&v, b.data() + off, sizeof(T));
  return v;
}

PointData read_bytes(const std::string& b, const std::string& name = "x.laz") {
  return read_las_memory(reinterpret_cast<const uint8_t*>(b.data()), b.size(), name);
}

std::string read_bytes_error(const std::string& b) {
  try {
    read_bytes(b);
  } catch (const ReadError& e) {
    return e.what();
  }
  return "(no error)";
}
#define EXPECT_READ_ERROR_MEM(bytes, needle)                                    \
  do {                                                                          \
    const std::string msg_ = read_bytes_error(bytes);                           \
    EXPECT_NE(msg_.find(needle), std::string::npos) << "message: " << msg_;     \
  } while (0)

// The laszip VLR's payload of a LAZ file.
laz::LaszipVlr laszip_vlr_of(const std::string& b) {
  size_t p = at<uint16_t>(b, 94);
  for (uint32_t i = 0; i < at<uint32_t>(b, 100); ++i) {
    const uint16_t len = at<uint16_t>(b, p + 20);
    if (std::string(b.data() + p + 2) == "laszip encoded")
      return laz::parse_laszip_vlr(reinterpret_cast<const uint8_t*>(b.data()) + p + 54, len,
                                   static_cast<int64_t>(p + 54));
    p += 54 + len;
  }
  ADD_FAILURE() << "no laszip VLR";
  return {};
}

// Decodes a LAZ file's records and compares them with its uncompressed twin's.
void expect_records_of_las_twin(const std::string& laz_name, const std::string& las_name, uint32_t points,
                                uint16_t record_length, const std::function<void(const laz::LaszipVlr&)>& check_vlr) {
  const std::string z = slurp(data_path(laz_name));
  const std::string l = slurp(data_path(las_name));
  const uint32_t count = at<uint32_t>(z, 107);
  const uint16_t rl = at<uint16_t>(z, 105);
  ASSERT_EQ(count, points);
  ASSERT_EQ(rl, record_length);
  ASSERT_EQ(rl, at<uint16_t>(l, 105));
  const auto vlr = laszip_vlr_of(z);
  check_vlr(vlr);
  const std::vector<uint8_t> records =
      laz::decompress(reinterpret_cast<const uint8_t*>(z.data()), z.size(), at<uint32_t>(z, 96),
                      z.size(), count, rl, vlr);
  ASSERT_EQ(records.size(), size_t{count} * rl);
  EXPECT_EQ(0, std::memcmp(records.data(), l.data() + at<uint32_t>(l, 96), records.size()));
}

TEST(IoLaz, AutzenRecordsEqualTheLasTwinByteForByte) {
  expect_records_of_las_twin("laz/laspy_autzen_trim.laz", "autzen_trim.las", 110000, 34,
                             [](const laz::LaszipVlr& vlr) { EXPECT_EQ(vlr.compressor, 2); });
}

TEST(IoLaz, WavePacketRecordsEqualTheLasTwinByteForByte) {
  // Format 5: POINT10, GPSTIME11, RGB12, WAVEPACKET13 and two extra bytes,
  // every way of coding a waveform's offset (tests/data/io/make_wavepacket_laz.py).
  expect_records_of_las_twin("laz/lazrs_wavepacket5.laz", "wavepacket5.las", 3000, 65,
                             [](const laz::LaszipVlr& vlr) {
                               ASSERT_EQ(vlr.items.size(), 5u);
                               EXPECT_EQ(vlr.items[3].type, laz::kWavePacket13);
                             });
}

TEST(IoLaz, EveryTestFileReads) {
  struct Case {
    const char* name;
    size_t points;
    int64_t point_format, compressor;
  };
  const Case cases[] = {
      {"laspy_autzen_trim.laz", 110000, 3, 2}, {"laspy_plane.laz", 28185, 3, 2},
      {"laspy_extra.laz", 1065, 3, 2},         {"laspy_1_4_w_evlr.laz", 1000, 6, 3},
      {"laspy_simple_with_page.copc.laz", 1065, 7, 3},
      {"pdal_laszip-generated.laz", 1065, 3, 2},
      {"pdal_liblas-generated.laz", 1065, 3, 2},
      {"pdal_laszip-generated_with2bytespadding.laz", 1065, 3, 2},
      {"pdal_simple-laszip-compressor-version-1.2r0.laz", 1065, 3, 1},
      {"pdal_lone-star-split-1.laz", 122893, 1, 2}, {"pdal_ept_tile_3-5-4-3.laz", 18266, 1, 2},
      {"pdal_faceraster_numerical_imprecision.laz", 18074, 3, 2},
      {"las_fullwave.laz", 10750, 10, 3},        {"lazrs_wavepacket5.laz", 3000, 5, 2}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const PointData d = read_las(data_path(std::string("laz/") + c.name));
    EXPECT_EQ(d.num_points(), c.points);
    EXPECT_EQ(std::get<int64_t>(d.metadata.at("point_format")), c.point_format);
    EXPECT_EQ(std::get<int64_t>(d.metadata.at("laszip_compressor")), c.compressor);
  }
}

TEST(IoLaz, EarlyPointwiseCompressorMatchesTheChunkedWriter) {
  // Three writers (and LASzip 1.2's version 1 items) stored the same points.
  const PointData ref = read_las(data_path("laz/pdal_laszip-generated.laz"));
  for (const char* name : {"pdal_simple-laszip-compressor-version-1.2r0.laz",
                           "pdal_liblas-generated.laz",
                           "pdal_laszip-generated_with2bytespadding.laz"}) {
    SCOPED_TRACE(name);
    const PointData d = read_las(data_path(std::string("laz/") + name));
    EXPECT_EQ(d.positions, ref.positions);
    for (const auto& a : ref.attributes) EXPECT_EQ(d.find(a.name)->values, a.values) << a.name;
  }
}

class IoLazCorrupt : public ::testing::TestWithParam<const char*> {};
// LAZ has no checksums: a flipped byte in a chunk's raw first point, or in
// a layer near its end, can decode to other values without any sign. The
// flips below go inside the large arithmetic-coded streams (chunks of
// thousands of points), where they shift where the data ends.
class IoLazFlipped : public ::testing::TestWithParam<const char*> {};

TEST_P(IoLazCorrupt, TruncatedCopiesRaiseReadError) {
  const std::string b = slurp(data_path(std::string("laz/") + GetParam()));
  const size_t point_offset = at<uint32_t>(b, 96);
  for (int k = 1; k < 40; ++k) {
    const size_t cut = point_offset + (b.size() - point_offset) * k / 40;
    SCOPED_TRACE(cut);
    EXPECT_THROW(read_bytes(b.substr(0, cut)), ReadError);
  }
  EXPECT_THROW(read_bytes(b.substr(0, b.size() - 1)), ReadError);
}

TEST_P(IoLazFlipped, FlippedBytesInChunksRaiseReadError) {
  const std::string b = slurp(data_path(std::string("laz/") + GetParam()));
  const size_t point_offset = at<uint32_t>(b, 96);
  const size_t table = static_cast<size_t>(at<int64_t>(b, point_offset));
  const size_t rl = at<uint16_t>(b, 105);
  // Past the first chunk's raw point and its layer sizes, up to the table.
  const size_t begin = point_offset + 8 + rl + 4 + 60;
  ASSERT_LT(begin, table);
  for (int k = 0; k < 24; ++k) {
    std::string c = b;
    const size_t pos = begin + (table - begin) * k / 24;
    c[pos] = static_cast<char>(c[pos] ^ 0x21);
    SCOPED_TRACE(pos);
    try {
      read_bytes(c);
      ADD_FAILURE() << "a flipped byte at " << pos << " went unnoticed";
    } catch (const ReadError& e) {
      EXPECT_NE(std::string(e.what()).find("LAZ chunk"), std::string::npos) << e.what();
    }
  }
}

TEST_P(IoLazCorrupt, WrongChunkTableAndCountsRaiseReadError) {
  const std::string b = slurp(data_path(std::string("laz/") + GetParam()));
  const size_t point_offset = at<uint32_t>(b, 96);
  const int64_t table = at<int64_t>(b, point_offset);
  for (int64_t shift : {-5, -1, 1, 3}) {
    std::string c = b;
    const int64_t t = table + shift;
    std::memcpy(c.data() + point_offset, &t, 8);
    SCOPED_TRACE(shift);
    EXPECT_THROW(read_bytes(c), ReadError);
  }
  std::string c = b;
  c[static_cast<size_t>(table) + 4] = static_cast<char>(c[static_cast<size_t>(table) + 4] + 1);
  EXPECT_THROW(read_bytes(c), ReadError);  // one chunk more than the data holds
  const bool las14 = b[25] >= 4;
  for (uint64_t count : {uint64_t{1} << 40, uint64_t{0xFFFFFFFF}, uint64_t{123456789}}) {
    if (!las14 && count > 0xFFFFFFFF) continue;  // the 32-bit count of LAS 1.0-1.3
    std::string d = b;
    if (las14) std::memcpy(d.data() + 247, &count, 8);
    const uint32_t legacy = static_cast<uint32_t>(count);
    std::memcpy(d.data() + 107, &legacy, 4);
    SCOPED_TRACE(count);
    EXPECT_THROW(read_bytes(d), ReadError);
  }
}

// Named Io* so that scripts/sanitize_tests.sh (filter 'Io*') runs them.
INSTANTIATE_TEST_SUITE_P(IoLazFiles, IoLazCorrupt,
                         ::testing::Values("laspy_autzen_trim.laz", "laspy_1_4_w_evlr.laz",
                                           "laspy_simple_with_page.copc.laz",
                                           "pdal_lone-star-split-1.laz", "laspy_extra.laz"));
INSTANTIATE_TEST_SUITE_P(IoLazFiles, IoLazFlipped,
                         ::testing::Values("laspy_autzen_trim.laz", "laspy_1_4_w_evlr.laz",
                                           "pdal_lone-star-split-1.laz", "laspy_extra.laz"));

TEST(IoLaz, UnsupportedItemsAreNamed) {
  std::string b = slurp(data_path("laz/laspy_autzen_trim.laz"));
  const size_t vlr = b.find("laszip encoded") - 2 + 54;
  std::string c = b;
  c[vlr + 34 + 6 * 1 + 4] = 9;  // GPSTIME11 version 9
  EXPECT_READ_ERROR_MEM(c, "LAZ item GPSTIME11 version 9 is not supported");
  c = b;
  c[vlr] = 7;  // compressor 7
  EXPECT_READ_ERROR_MEM(c, "LAZ file uses compressor 7");
  c = b;
  c[vlr + 34 + 6 * 2] = 42;  // item type 42
  EXPECT_READ_ERROR_MEM(c, "LAZ item unknown item type 42 version 2");
}

}  // namespace
}  // namespace pointnpr
