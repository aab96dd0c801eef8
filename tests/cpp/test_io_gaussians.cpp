// 3D Gaussian splat files (io/gaussians.h, io/spz_reader.cpp): a real
// capture in SPZ, the committed synthetic SPZ v2 / v3 files of the same
// splats, every truncation and byte flip of an SPZ file a ReadError or a
// consistent result (tests/python/test_io_gaussians.py checks the values
// against the PLY of the same splats).
#include <cmath>
#include <fstream>
#include <iterator>

#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::attr;
using test_io::data_path;

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void expect_consistent(const PointData& d) {
  const size_t n = d.num_points();
  for (const PointAttribute& a : d.attributes)
    EXPECT_EQ(std::visit([](const auto& v) { return v.size(); }, a.values), n * size_t(a.components)) << a.name;
}

TEST(IoGaussians, ARealCaptureInSpz) {
  const PointData d = read_point_cloud(data_path("gaussians/playbot_lod3.spz"));
  ASSERT_EQ(d.num_points(), 31000u);
  EXPECT_EQ(std::get<std::string>(d.metadata.at("format")), "spz");
  EXPECT_EQ(std::get<int64_t>(d.metadata.at("sh_degree")), 2);
  EXPECT_EQ(std::get<int64_t>(d.metadata.at("gaussian_splats")), 1);
  expect_consistent(d);
  const auto& opacity = attr<float>(d, "opacity");
  const auto& scales = attr<float>(d, "scales");
  const auto& rotations = attr<float>(d, "rotations");
  EXPECT_EQ(attr<float>(d, "sh").size(), 31000u * 27u);
  EXPECT_EQ(attr<uint8_t>(d, "colors").size(), 31000u * 3u);
  for (size_t i = 0; i < d.num_points(); ++i) {
    ASSERT_TRUE(opacity[i] >= 0.0f && opacity[i] <= 1.0f);
    for (int a = 0; a < 3; ++a) ASSERT_GT(scales[3 * i + size_t(a)], 0.0f);
    float len = 0.0f;
    for (int a = 0; a < 4; ++a) len += rotations[4 * i + size_t(a)] * rotations[4 * i + size_t(a)];
    ASSERT_NEAR(len, 1.0f, 1e-5f);
  }
}

TEST(IoGaussians, SpzVersionsTwoAndThreeOfOneCloudAgree) {
  const PointData v2 = read_point_cloud(data_path("gaussians/synthetic_v2.spz"));
  const PointData v3 = read_point_cloud(data_path("gaussians/synthetic_v3.spz"));
  ASSERT_EQ(v2.num_points(), 64u);
  ASSERT_EQ(v3.num_points(), 64u);
  EXPECT_EQ(v2.positions, v3.positions);  // the same 24-bit fixed point
  EXPECT_EQ(attr<float>(v2, "opacity"), attr<float>(v3, "opacity"));
  EXPECT_EQ(attr<float>(v2, "sh"), attr<float>(v3, "sh"));
  const auto& a = attr<float>(v2, "rotations");
  const auto& b = attr<float>(v3, "rotations");
  for (size_t i = 0; i < 64; ++i) {
    float dot = 0.0f;  // q and -q are one rotation
    for (int k = 0; k < 4; ++k) dot += a[4 * i + size_t(k)] * b[4 * i + size_t(k)];
    EXPECT_GT(std::abs(dot), 0.98f) << i;
  }
}

TEST(IoGaussians, EveryTruncationOfAnSpzFileIsAReadError) {
  for (const char* name : {"gaussians/synthetic_v3.spz", "gaussians/synthetic_v4.spz"}) {
    const std::vector<uint8_t> bytes = file_bytes(data_path(name));
    ASSERT_GT(bytes.size(), 100u);
    for (size_t size = 0; size < bytes.size(); ++size)
      EXPECT_THROW(read_spz_memory(bytes.data(), size, "cut.spz"), ReadError) << name << " " << size;
    EXPECT_EQ(read_spz_memory(bytes.data(), bytes.size(), "whole.spz").num_points(), 64u);
  }
}

TEST(IoGaussians, FlippedBytesGiveAReadErrorOrAConsistentCloud) {
  // Version 2's gzip CRC-32 and version 4's zstd checksums catch changed data.
  for (const char* name : {"gaussians/synthetic_v2.spz", "gaussians/synthetic_v4.spz"}) {
    std::vector<uint8_t> bytes = file_bytes(data_path(name));
    size_t errors = 0;
    for (size_t at = 0; at < bytes.size(); at += 7) {
      std::vector<uint8_t> bad = bytes;
      bad[at] ^= 0x5a;
      try {
        expect_consistent(read_spz_memory(bad.data(), bad.size(), "flipped.spz"));
      } catch (const ReadError&) {
        ++errors;
      }
    }
    EXPECT_GT(errors, bytes.size() / 7 / 2) << name;
  }
}

TEST(IoGaussians, APartial3dgsPlyIsAReadError) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\nproperty float opacity\n"
      "end_header\n0 0 0 0.1 0.2 0.3 0\n";
  try {
    read_ply_memory(reinterpret_cast<const uint8_t*>(ply.data()), ply.size(), "partial.ply");
    FAIL() << "no ReadError";
  } catch (const ReadError& e) {
    EXPECT_NE(std::string(e.what()).find("scale_0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pointnpr
