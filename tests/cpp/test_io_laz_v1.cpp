// LASzip 1.x items (version 1) written by the test-side encoder
// (laz_test_encoder.h), since no real LAZ file with BYTE v1 was found:
// POINT10 v1 + BYTE v1 point-wise files decode to the records encoded, in
// every field; POINT10 v1 alone too (its decoder is verified against the
// real pdal_simple-laszip-compressor-version-1.2r0.laz, which keeps the
// encoder honest); truncated copies, and chunked ones with a flipped byte
// in a stream, raise ReadError. The two files in
// tests/data/io/laz/pointnpr_v1_*.laz are this encoder's output (checked
// here byte for byte) and are compared with laspy's reading of their LAS
// twins, and (chunked POINT10 v1) with lazrs, in tests/python/test_io_laz.py.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "io/laz_reader.h"
#include "laz_test_encoder.h"
#include "test_io_util.h"

namespace pointnpr {
namespace {

using namespace test_io;

constexpr size_t kExtra = 7;

// Seeded points of format 0: x/y random walks with occasional jumps of any
// size (wrapping the 32-bit differences), every field changing now and then.
std::vector<LasPoint> v1_points(size_t n, size_t extra, uint32_t seed) {
  std::mt19937 rng(seed);
  auto u = [&rng](uint32_t m) { return static_cast<uint32_t>(rng() % m); };
  std::vector<LasPoint> pts(n);
  int32_t x = 100000, y = -50000, z = 2000;
  LasPoint last;
  uint8_t walk = 250;
  for (size_t i = 0; i < n; ++i) {
    LasPoint p = last;
    x = u(20) == 0 ? static_cast<int32_t>(rng()) : x + static_cast<int32_t>(u(401)) - 200;
    y = u(25) == 0 ? static_cast<int32_t>(rng()) : y + static_cast<int32_t>(u(101)) - 50;
    z = u(30) == 0 ? static_cast<int32_t>(rng()) : z + static_cast<int32_t>(u(21)) - 10;
    p.x = x, p.y = y, p.z = z;
    if (u(3) == 0) p.intensity = static_cast<uint16_t>(u(4) == 0 ? u(65536) : u(300));
    if (u(4) == 0) {
      p.number_of_returns = static_cast<uint8_t>(1 + u(5));
      p.return_number = static_cast<uint8_t>(1 + u(p.number_of_returns));
    }
    if (u(6) == 0) p.classification = static_cast<uint8_t>(u(256));  // flags in bits 5-7 too
    if (u(5) == 0) p.scan_angle = static_cast<double>(static_cast<int>(u(181)) - 90);
    if (u(9) == 0) p.user_data = static_cast<uint8_t>(u(256));
    if (u(40) == 0) p.point_source_id = static_cast<uint16_t>(u(65536));
    // Extra bytes: random; constant; 0/255 alternating (the widest wrap);
    // a counter wrapping 255 -> 0; jumps of 128; a small walk across 0/255;
    // 0 or 255 at random.
    walk = static_cast<uint8_t>(walk + static_cast<int>(u(7)) - 3);
    const uint8_t b[kExtra] = {static_cast<uint8_t>(rng()),
                               0x5A,
                               static_cast<uint8_t>(i % 2 ? 255 : 0),
                               static_cast<uint8_t>(i),
                               static_cast<uint8_t>((i % 3 ? 0x80 : 0x00) ^ u(3)),
                               walk,
                               static_cast<uint8_t>(u(2) ? 255 : 0)};
    p.extra.assign(reinterpret_cast<const char*>(b), extra);
    pts[i] = last = p;
  }
  return pts;
}

LasSpec v1_spec(size_t n, size_t extra, uint32_t seed) {
  LasSpec s;
  s.point_format = 0;
  s.points = v1_points(n, extra, seed);
  if (extra) {
    std::string d;
    for (size_t i = 0; i < extra; ++i) d += extra_bytes_descriptor("b" + std::to_string(i), 1, false);
    s.vlrs.push_back({"LASF_Spec", 4, d});
  }
  return s;
}

std::string records_of(const LasSpec& s) {
  std::string r;
  for (const LasPoint& p : s.points) r += las_point_bytes(s, p);
  return r;
}

// The LAZ file of `spec`'s points: its LAS header and VLRs plus the LASzip
// VLR, the point format's compression bit, the encoded point data.
std::string make_laz_v1(LasSpec spec, int compressor, size_t chunk_size = 500) {
  const size_t rl = 20 + (spec.points.empty() ? 0 : spec.points[0].extra.size());
  spec.vlrs.push_back(
      {"laszip encoded", 22204, laz_test::laszip_vlr_payload_v1(static_cast<uint16_t>(compressor),
                                                                rl - 20, static_cast<uint32_t>(chunk_size))});
  std::string f = make_las(spec);
  uint32_t point_offset;
  std::memcpy(&point_offset, f.data() + 96, 4);
  f.resize(point_offset);
  f[104] = static_cast<char>(f[104] | 0x80);
  return f + laz_test::laz_point_data_v1(records_of(spec), rl, compressor, chunk_size, point_offset);
}

PointData read_mem(const std::string& b, const std::string& name) {
  return read_las_memory(reinterpret_cast<const uint8_t*>(b.data()), b.size(), name);
}

// Decodes `laz` and checks every record byte, and every column the reader
// makes, against the LAS twin of the same points.
void expect_decodes_to(const std::string& laz, const LasSpec& spec) {
  const std::string las = make_las(spec);
  const std::string records = records_of(spec);
  const size_t rl = records.size() / spec.points.size();
  uint32_t point_offset;
  std::memcpy(&point_offset, laz.data() + 96, 4);
  const laz::LaszipVlr vlr = [&] {
    const size_t at = laz.find("laszip encoded") - 2 + 54;
    uint16_t len;
    std::memcpy(&len, laz.data() + at - 34, 2);
    return laz::parse_laszip_vlr(reinterpret_cast<const uint8_t*>(laz.data()) + at, len,
                                 static_cast<int64_t>(at));
  }();
  const std::vector<uint8_t> decoded =
      laz::decompress(reinterpret_cast<const uint8_t*>(laz.data()), laz.size(), point_offset,
                      laz.size(), spec.points.size(), rl, vlr);
  ASSERT_EQ(decoded.size(), records.size());
  for (size_t i = 0; i < spec.points.size(); ++i)
    ASSERT_EQ(0, std::memcmp(decoded.data() + i * rl, records.data() + i * rl, rl)) << "point " << i;

  const PointData a = read_mem(laz, "v1.laz"), b = read_mem(las, "v1.las");
  EXPECT_EQ(a.num_points(), spec.points.size());
  EXPECT_EQ(a.positions, b.positions);
  ASSERT_EQ(a.attributes.size(), b.attributes.size());
  for (const auto& col : b.attributes) {
    ASSERT_NE(a.find(col.name), nullptr) << col.name;
    EXPECT_EQ(a.find(col.name)->values, col.values) << col.name;
  }
  for (size_t i = 0; i + 20 < rl; ++i) EXPECT_NE(a.find("b" + std::to_string(i)), nullptr);
}

TEST(IoLazV1, ByteV1PointwiseDecodesEveryField) {
  const LasSpec spec = v1_spec(3000, kExtra, 7);
  const std::string laz = make_laz_v1(spec, 1);
  expect_decodes_to(laz, spec);
  const PointData d = read_mem(laz, "v1.laz");
  EXPECT_EQ(std::get<int64_t>(d.metadata.at("laszip_compressor")), 1);
}

TEST(IoLazV1, ByteV1OfOneByteAndInChunksDecodes) {
  // One extra byte; and chunks (each restarting every model from a raw point).
  const LasSpec one = v1_spec(1200, 1, 11);
  expect_decodes_to(make_laz_v1(one, 1), one);
  const LasSpec chunked = v1_spec(1234, kExtra, 12);
  expect_decodes_to(make_laz_v1(chunked, 2, 300), chunked);
}

TEST(IoLazV1, Point10V1AloneRoundTrips) {
  // The POINT10 v1 decoder reads LASzip 1.2's real file exactly
  // (test_io_laz.cpp), so this checks the encoder as much as the decoder.
  const LasSpec spec = v1_spec(2500, 0, 5);
  expect_decodes_to(make_laz_v1(spec, 1), spec);
  expect_decodes_to(make_laz_v1(spec, 2, 1000), spec);
}

TEST(IoLazV1, TruncatedByteV1FilesRaiseReadError) {
  const std::string b = make_laz_v1(v1_spec(2000, kExtra, 9), 1);
  uint32_t point_offset;
  std::memcpy(&point_offset, b.data() + 96, 4);
  for (int k = 0; k < 40; ++k) {
    const size_t cut = point_offset + (b.size() - point_offset) * k / 40;
    SCOPED_TRACE(cut);
    EXPECT_THROW(read_mem(b.substr(0, cut), "cut.laz"), ReadError);
  }
  for (size_t drop : {1, 2, 5}) {
    SCOPED_TRACE(drop);
    try {
      read_mem(b.substr(0, b.size() - drop), "cut.laz");
      ADD_FAILURE() << "a file missing its last " << drop << " bytes read";
    } catch (const ReadError& e) {
      EXPECT_NE(std::string(e.what()).find("LAZ point data is corrupt"), std::string::npos) << e.what();
    }
  }
}

TEST(IoLazV1, FlippedBytesInByteV1ChunksRaiseReadError) {
  // Chunked, so that a chunk's stream must end where the table says. LAZ
  // has no checksums: the flips go inside the arithmetic-coded streams, not
  // the raw first point of a chunk (which would decode to other values).
  const size_t rl = 20 + kExtra, chunk = 600;
  const LasSpec spec = v1_spec(2400, kExtra, 10);
  const std::string b = make_laz_v1(spec, 2, chunk);
  const std::string records = records_of(spec);
  uint32_t point_offset;
  std::memcpy(&point_offset, b.data() + 96, 4);
  size_t start = point_offset + 8;
  for (size_t i = 0; i * chunk < spec.points.size(); ++i) {
    const size_t size =
        laz_test::encode_stream_v1(reinterpret_cast<const uint8_t*>(records.data()) + i * chunk * rl,
                                   chunk, rl)
            .size();
    for (size_t j = 1; j < 5; ++j) {
      std::string c = b;
      const size_t pos = start + rl + (size - rl) * j / 5;
      c[pos] = static_cast<char>(c[pos] ^ 0x21);
      SCOPED_TRACE(pos);
      try {
        read_mem(c, "flip.laz");
        ADD_FAILURE() << "a flipped byte at " << pos << " went unnoticed";
      } catch (const ReadError& e) {
        EXPECT_NE(std::string(e.what()).find("LAZ chunk " + std::to_string(i)), std::string::npos)
            << e.what();
      }
    }
    start += size;
  }
}

// The committed files are this encoder's output for fixed seeds: the test
// data (with LAS twins) and two small fuzz_laz seeds. Setting
// POINTNPR_WRITE_LAZ_V1=1 rewrites them in place.
TEST(IoLazV1, CommittedFilesAreTheEncodersOutput) {
  struct File {
    std::string path;  // without extension
    LasSpec spec;
    int compressor;
    size_t chunk_size;
    bool twin;
  };
  const std::string seeds = "../../../fuzz/seeds/laz/";
  const File files[] = {{"laz/pointnpr_v1_bytes", v1_spec(1500, kExtra, 2026), 1, 500, true},
                        {"laz/pointnpr_v1_chunked", v1_spec(1500, 0, 1202), 2, 500, true},
                        {seeds + "v1_bytes_small", v1_spec(60, 3, 31), 1, 500, false},
                        {seeds + "v1_bytes_chunked_small", v1_spec(70, 2, 32), 2, 25, false}};
  const bool rewrite = std::getenv("POINTNPR_WRITE_LAZ_V1") != nullptr;
  auto file = [](const std::string& path) {
    std::ifstream f(data_path(path), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  for (const File& f : files) {
    SCOPED_TRACE(f.path);
    const std::string laz = make_laz_v1(f.spec, f.compressor, f.chunk_size);
    const std::string las = make_las(f.spec);
    if (rewrite) {
      std::ofstream(data_path(f.path + ".laz"), std::ios::binary) << laz;
      if (f.twin) std::ofstream(data_path(f.path + ".las"), std::ios::binary) << las;
    }
    // (Compared as booleans: a diff of binary files is no help.)
    EXPECT_TRUE(file(f.path + ".laz") == laz);
    if (f.twin) {
      EXPECT_TRUE(file(f.path + ".las") == las);
    }
    expect_decodes_to(laz, f.spec);
  }
}

}  // namespace
}  // namespace pointnpr
