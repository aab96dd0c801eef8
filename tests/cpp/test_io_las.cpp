// LAS reader: real files (point counts, exact coordinates, attributes),
// malformed files from other projects' test suites, and generated files for
// each point format feature.
#include <set>

#include <iterator>

#include "io/mapped_file.h"
#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::attr;
using test_io::data_path;
using test_io::LasPoint;
using test_io::LasSpec;
using test_io::LasVlr;
using test_io::make_las;
using test_io::write_file;

int64_t md_int(const PointData& d, const std::string& key) {
  return std::get<int64_t>(d.metadata.at(key));
}
std::string md_str(const PointData& d, const std::string& key) {
  return std::get<std::string>(d.metadata.at(key));
}

// ---------------------------------------------------------------- real scans

TEST(IoLas, WarsawSmall) {
  PointData d = read_point_cloud(data_path("warsaw_small.las"));
  ASSERT_EQ(d.num_points(), 3000u);
  EXPECT_EQ(md_str(d, "format"), "las");
  EXPECT_EQ(md_str(d, "version"), "1.2");
  EXPECT_EQ(md_int(d, "point_format"), 3);
  EXPECT_EQ(d.positions[0], 639944.97);
  EXPECT_EQ(d.positions[1], 485154.44);
  EXPECT_EQ(d.positions[2], 84.82000000000001);
  EXPECT_EQ(d.positions[3 * 2999 + 0], 639930.4);
  EXPECT_EQ(d.positions[3 * 2999 + 2], 102.86);
  const auto& c = attr<uint8_t>(d, "colors");
  ASSERT_EQ(c.size(), 3u * 3000);
  EXPECT_EQ(md_int(d, "color_bits"), 16);
  // 16-bit (32256, 30976, 26368) -> high bytes.
  EXPECT_EQ(c[0], 126);
  EXPECT_EQ(c[1], 121);
  EXPECT_EQ(c[2], 103);
  EXPECT_EQ(attr<float>(d, "intensity")[0], 633.f);
  EXPECT_EQ(attr<uint8_t>(d, "classification")[0], 3);
  EXPECT_EQ(attr<uint8_t>(d, "classification")[2999], 5);
  EXPECT_DOUBLE_EQ(attr<double>(d, "gps_time")[0], 206946275.5600586);
  EXPECT_FALSE(d.metadata.count("crs_wkt"));  // the file's WKT VLR is a placeholder
}

TEST(IoLas, MvkThinFormat1) {
  PointData d = read_point_cloud(data_path("mvk-thin.las"));
  ASSERT_EQ(d.num_points(), 6280u);
  EXPECT_EQ(md_int(d, "point_format"), 1);
  EXPECT_FALSE(d.has("colors"));
  EXPECT_EQ(d.positions[0], 2045008.1700000002);
  EXPECT_EQ(d.positions[1], 1272222.6400000001);
  EXPECT_EQ(d.positions[2], 106.61);
  EXPECT_EQ(attr<double>(d, "gps_time")[0], 339486.8416735852);
  EXPECT_EQ(attr<uint8_t>(d, "classification")[0], 12);
  EXPECT_EQ(attr<float>(d, "intensity")[6279], 87.f);
  EXPECT_EQ(md_int(d, "crs_epsg"), 26995);
}

TEST(IoLas, SampleCOddOffsets) {
  PointData d = read_point_cloud(data_path("sample_c.las"));
  ASSERT_EQ(d.num_points(), 14408u);
  EXPECT_EQ(d.positions[0], 674522.0000134277);
  EXPECT_EQ(d.positions[1], 1206771.7500170898);
  EXPECT_EQ(d.positions[2], 627.590029296875);
  EXPECT_EQ(d.positions[3 * 14407 + 0], 674602.9700134278);
  std::set<int> classes(attr<uint8_t>(d, "classification").begin(),
                        attr<uint8_t>(d, "classification").end());
  EXPECT_EQ(classes, (std::set<int>{2, 3, 4, 5, 6, 11, 14, 31}));
  const auto& c = attr<uint8_t>(d, "colors");
  EXPECT_EQ(c[0], 48896 >> 8);
  EXPECT_EQ(c[1], 51712 >> 8);
  EXPECT_EQ(c[2], 49408 >> 8);
}

TEST(IoLas, NebraskaFormat6WithWktAndGeoKeys) {
  PointData d = read_point_cloud(data_path("laspy_nebraska_classified.las"));
  ASSERT_EQ(d.num_points(), 25408u);  // legacy count is 0: the 64-bit count is used
  EXPECT_EQ(md_str(d, "version"), "1.4");
  EXPECT_EQ(md_int(d, "point_format"), 6);
  EXPECT_EQ(d.positions[0], 2445180.75);
  EXPECT_EQ(d.positions[1], 604324.04);
  EXPECT_EQ(d.positions[2], 1354.22);
  EXPECT_NE(md_str(d, "crs_wkt").find("NAD83_2011_Nebraska_ft"), std::string::npos);
  EXPECT_EQ(md_int(d, "crs_epsg"), 32104);
  EXPECT_EQ(attr<float>(d, "intensity")[0], 42399.f);
  std::set<int> classes(attr<uint8_t>(d, "classification").begin(),
                        attr<uint8_t>(d, "classification").end());
  EXPECT_EQ(classes, (std::set<int>{2, 3, 4, 5, 6, 7}));
  EXPECT_FALSE(d.has("colors"));
}

TEST(IoLas, LidarHdFormat8WithNir) {
  PointData d = read_point_cloud(data_path("lidarhd_myria3d_subset.las"));
  ASSERT_EQ(d.num_points(), 2000u);
  EXPECT_EQ(md_int(d, "point_format"), 8);
  EXPECT_EQ(d.positions[0], 870277.39);
  EXPECT_EQ(d.positions[1], 6617096.36);
  EXPECT_EQ(d.positions[2], 180.06);
  EXPECT_EQ(d.positions[3 * 1999 + 2], 185.32999999999998);
  const auto& c = attr<uint8_t>(d, "colors");
  EXPECT_EQ(c[0], 149);
  EXPECT_EQ(c[1], 154);
  EXPECT_EQ(c[2], 127);
  EXPECT_EQ(attr<uint16_t>(d, "nir").size(), 2000u);
  EXPECT_EQ(attr<uint8_t>(d, "classification")[0], 6);
  EXPECT_EQ(attr<double>(d, "gps_time")[0], 297417272.391274);
}

TEST(IoLas, LionFormat7WithExtraBytes) {
  PointData d = read_point_cloud(data_path("lion_takanawa_subset.las"));
  ASSERT_EQ(d.num_points(), 2000u);
  EXPECT_EQ(md_int(d, "point_format"), 7);
  EXPECT_EQ(d.positions[0], -3.2600000000000002);
  EXPECT_EQ(d.positions[1], 3.6);
  EXPECT_EQ(d.positions[2], -1.33);
  const auto& origin = attr<uint32_t>(d, "OriginId");  // described by the extra bytes VLR
  EXPECT_EQ(origin[0], 41u);
  EXPECT_EQ(origin[1999], 140u);
  EXPECT_EQ(attr<uint8_t>(d, "colors")[0], 22528 >> 8);
  EXPECT_FALSE(d.metadata.count("extra_bytes_undescribed"));
}

// ------------------------------------------------- other projects' test files

TEST(IoLas, ValidOddFiles) {
  struct Case {
    const char* file;
    size_t points;
    int point_format;
    double x0;
  };
  const Case cases[] = {
      {"malformed/las_pdal_100-points.las", 100, 3, 636782.3200000001},
      {"malformed/las_pdal_permutations_1.0_0.las", 1, 0, 470692.44},
      {"malformed/las_pdal_permutations_1.1_0.las", 1, 0, 470692.44},
      {"malformed/las_pdal_permutations_1.2_0.las", 1, 0, 470692.44},
      {"malformed/las_pdal_permutations_1.2_2.las", 1, 2, 470692.44},
      {"malformed/las_pdal_lots_of_vlr.las", 1, 1, 715001.346},
      {"malformed/las_pdal_prec3.las", 110, 3, 637177.98},
      {"malformed/las_pdal_spurious.las", 1065, 3, -124.0687348},
      {"malformed/las_pdal_test1_4.las", 1000, 6, 1694510.3869346841},
      {"malformed/las_laspy_simple1_3.las", 999, 4, -234935.84100000001},
      {"malformed/las_laspy_unregistered_extra_bytes.las", 4, 6, 1.0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    PointData d = read_point_cloud(data_path(c.file));
    EXPECT_EQ(d.num_points(), c.points);
    EXPECT_EQ(md_int(d, "point_format"), c.point_format);
    ASSERT_GT(d.num_points(), 0u);
    EXPECT_EQ(d.positions[0], c.x0);
    EXPECT_EQ(attr<float>(d, "intensity").size(), c.points);
  }
}

TEST(IoLas, DetailsOfOddFiles) {
  PointData hundred = read_point_cloud(data_path("malformed/las_pdal_100-points.las"));
  EXPECT_EQ(md_int(hundred, "color_bits"), 8);  // values 0-255 are used as they are
  EXPECT_EQ(attr<uint8_t>(hundred, "colors")[0], 140);
  EXPECT_EQ(attr<uint8_t>(hundred, "colors")[1], 104);
  EXPECT_EQ(attr<uint8_t>(hundred, "colors")[2], 132);
  EXPECT_EQ(attr<uint8_t>(hundred, "return_number")[99], 2);

  PointData t14 = read_point_cloud(data_path("malformed/las_pdal_test1_4.las"));
  EXPECT_NE(md_str(t14, "crs_wkt").find("New Mexico Central"), std::string::npos);
  EXPECT_EQ(t14.positions[2], 5598.3596128149675);

  PointData wave = read_point_cloud(data_path("malformed/las_laspy_simple1_3.las"));
  EXPECT_EQ(md_str(wave, "version"), "1.3");
  EXPECT_EQ(md_int(wave, "waveform_ignored"), 1);
  EXPECT_EQ(attr<double>(wave, "gps_time")[0], 129850.00006503289);

  PointData unreg = read_point_cloud(data_path("malformed/las_laspy_unregistered_extra_bytes.las"));
  EXPECT_EQ(md_int(unreg, "extra_bytes_undescribed"), 4);
  EXPECT_EQ(unreg.positions[3 * 3], 4.0);

  PointData v10 = read_point_cloud(data_path("malformed/las_pdal_permutations_1.0_0.las"));
  EXPECT_EQ(md_str(v10, "version"), "1.0");
  EXPECT_EQ(md_int(v10, "crs_epsg"), 26915);
  EXPECT_EQ(attr<uint8_t>(v10, "classification")[0], 2);
  EXPECT_EQ(attr<uint8_t>(v10, "return_number")[0], 2);
}

TEST(IoLas, BrokenFilesAreRefused) {
  EXPECT_READ_ERROR(data_path("malformed/las_pdal_1.2-no-points_truncated.las"),
                    "file is truncated: the header declares 1065 points of 34 bytes");
  EXPECT_READ_ERROR(data_path("malformed/las_pdal_bad_vlr_count.las"),
                    "variable length record 3 of 3 would start at byte 429");
  EXPECT_READ_ERROR(data_path("malformed/las_pdal_garbage_nVariableLength.las"),
                    "header declares 1069128089 variable length records");
}

// ------------------------------------------------------------ generated files

LasSpec spec_with_points(int minor, int pf, size_t n) {
  LasSpec s;
  s.version_minor = minor;
  s.point_format = pf;
  for (size_t i = 0; i < n; ++i) {
    LasPoint p;
    p.x = static_cast<int32_t>(1000 + i);
    p.y = static_cast<int32_t>(-2000 - static_cast<int>(i));
    p.z = static_cast<int32_t>(i * 7);
    p.intensity = static_cast<uint16_t>(100 * i);
    p.classification = static_cast<uint8_t>(i % 20);
    p.gps_time = 1.5 * static_cast<double>(i);
    s.points.push_back(p);
  }
  return s;
}

TEST(IoLasGenerated, ExactGeoreferencedCoordinates) {
  LasSpec s = spec_with_points(2, 0, 3);
  s.scale[0] = 0.001;
  s.scale[1] = 0.001;
  s.scale[2] = 0.0001;
  s.offset[0] = 870200.0;
  s.offset[1] = 6617080.0;
  s.offset[2] = 179.13;
  s.points[1].x = 2147483647;
  s.points[1].y = -2147483647 - 1;
  s.points[2].z = 123456789;
  PointData d = read_point_cloud(write_file("exact.las", make_las(s)));
  ASSERT_EQ(d.num_points(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(d.positions[3 * i + 0], static_cast<double>(s.points[i].x) * 0.001 + 870200.0);
    EXPECT_EQ(d.positions[3 * i + 1], static_cast<double>(s.points[i].y) * 0.001 + 6617080.0);
    EXPECT_EQ(d.positions[3 * i + 2], static_cast<double>(s.points[i].z) * 0.0001 + 179.13);
  }
  auto scale = std::get<std::vector<double>>(d.metadata.at("scale"));
  EXPECT_EQ(scale, (std::vector<double>{0.001, 0.001, 0.0001}));
}

TEST(IoLasGenerated, LegacyClassificationFlagsAndReturns) {
  LasSpec s = spec_with_points(2, 1, 2);
  s.points[0].classification = 0xE0 | 5;  // synthetic + key-point + withheld flags, class 5
  s.points[0].return_number = 3;
  s.points[0].number_of_returns = 5;
  s.points[0].scan_angle = -12;
  PointData d = read_point_cloud(write_file("legacy_flags.las", make_las(s)));
  EXPECT_EQ(attr<uint8_t>(d, "classification")[0], 5);
  EXPECT_EQ(attr<uint8_t>(d, "return_number")[0], 3);
  EXPECT_EQ(attr<uint8_t>(d, "number_of_returns")[0], 5);
  EXPECT_EQ(attr<float>(d, "scan_angle")[0], -12.f);
  EXPECT_EQ(attr<double>(d, "gps_time")[1], 1.5);
}

TEST(IoLasGenerated, Format6ExtendedFieldsAndExtraBytes) {
  LasSpec s = spec_with_points(4, 6, 4);
  s.vlrs.push_back(LasVlr{"LASF_Spec", 4,
                          test_io::extra_bytes_descriptor("height", 4 /*short*/, true, 0.01, 100.0) +
                              test_io::extra_bytes_descriptor("tag", 1 /*uchar*/, false) +
                              test_io::extra_bytes_descriptor("normal", 29 /*3 x float*/, false)});
  for (size_t i = 0; i < s.points.size(); ++i) {
    LasPoint& p = s.points[i];
    p.classification = static_cast<uint8_t>(64 + i);  // extended classes use all 8 bits
    p.return_number = 9;
    p.number_of_returns = 15;
    p.scan_angle = -30.0;
    test_io::Bytes e;
    e.put<int16_t>(static_cast<int16_t>(-150 + static_cast<int>(i)));
    e.put<uint8_t>(static_cast<uint8_t>(200 + i));
    e.put<float>(0.5f).put<float>(-0.25f).put<float>(static_cast<float>(i));
    p.extra = e.s;
  }
  PointData d = read_point_cloud(write_file("f6_extra.las", make_las(s)));
  ASSERT_EQ(d.num_points(), 4u);  // the legacy count is 0, the 64-bit count 4
  EXPECT_EQ(md_int(d, "point_format"), 6);
  EXPECT_EQ(md_int(d, "point_record_length"), 30 + 2 + 1 + 12);
  EXPECT_EQ(attr<uint8_t>(d, "classification")[3], 67);
  EXPECT_EQ(attr<uint8_t>(d, "return_number")[0], 9);
  EXPECT_EQ(attr<uint8_t>(d, "number_of_returns")[0], 15);
  EXPECT_NEAR(attr<float>(d, "scan_angle")[0], -30.f, 1e-4);
  EXPECT_EQ(attr<double>(d, "gps_time")[2], 3.0);
  const auto& height = attr<double>(d, "height");  // scaled -> float64
  EXPECT_DOUBLE_EQ(height[0], -150 * 0.01 + 100.0);
  EXPECT_DOUBLE_EQ(height[3], -147 * 0.01 + 100.0);
  EXPECT_EQ(attr<uint8_t>(d, "tag")[1], 201);
  const PointAttribute* normal = d.find("normal");
  ASSERT_NE(normal, nullptr);
  EXPECT_EQ(normal->components, 3);
  const auto& nv = attr<float>(d, "normal");
  EXPECT_EQ(nv[3 * 2 + 0], 0.5f);
  EXPECT_EQ(nv[3 * 2 + 1], -0.25f);
  EXPECT_EQ(nv[3 * 2 + 2], 2.0f);
  EXPECT_FALSE(d.has("colors"));
}

TEST(IoLasGenerated, Format7EightBitColourAndFloatExtraBytes) {
  LasSpec s = spec_with_points(4, 7, 3);
  s.vlrs.push_back(LasVlr{"LASF_Spec", 4, test_io::extra_bytes_descriptor("reflectance", 9, false)});
  for (size_t i = 0; i < 3; ++i) {
    s.points[i].rgb[0] = 255;
    s.points[i].rgb[1] = static_cast<uint16_t>(10 * i);
    s.points[i].rgb[2] = 0;
    test_io::Bytes e;
    e.put<float>(-3.5f * static_cast<float>(i));
    s.points[i].extra = e.s;
  }
  PointData d = read_point_cloud(write_file("f7_extra.las", make_las(s)));
  EXPECT_EQ(md_int(d, "color_bits"), 8);
  const auto& c = attr<uint8_t>(d, "colors");
  EXPECT_EQ(c[3 * 2 + 0], 255);
  EXPECT_EQ(c[3 * 2 + 1], 20);
  EXPECT_EQ(attr<float>(d, "reflectance")[2], -7.0f);
}

TEST(IoLasGenerated, SixteenVersusEightBitColour) {
  LasSpec s16 = spec_with_points(2, 2, 3);
  LasSpec s8 = spec_with_points(2, 2, 3);
  const uint16_t c8[3][3] = {{255, 128, 0}, {1, 2, 3}, {200, 100, 50}};
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) {
      s8.points[i].rgb[c] = c8[i][c];
      s16.points[i].rgb[c] = static_cast<uint16_t>(c8[i][c] * 257);  // full 16-bit range
    }
  s16.points[1].rgb[0] = 65535;
  PointData d8 = read_point_cloud(write_file("rgb8.las", make_las(s8)));
  PointData d16 = read_point_cloud(write_file("rgb16.las", make_las(s16)));
  EXPECT_EQ(md_int(d8, "color_bits"), 8);
  EXPECT_EQ(md_int(d16, "color_bits"), 16);
  const auto& a = attr<uint8_t>(d8, "colors");
  const auto& b = attr<uint8_t>(d16, "colors");
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(a[3 * i + c], c8[i][c]);
      EXPECT_EQ(b[3 * i + c], (i == 1 && c == 0) ? 255 : c8[i][c]);
    }
  // Colour widened by shifting (c * 256) maps back exactly as well.
  LasSpec shifted = s8;
  for (auto& p : shifted.points)
    for (auto& v : p.rgb) v = static_cast<uint16_t>(v << 8);
  PointData ds = read_point_cloud(write_file("rgb_shift.las", make_las(shifted)));
  EXPECT_EQ(attr<uint8_t>(ds, "colors"), a);

  // All-zero colour carries no information: no "colors" attribute.
  PointData dz = read_point_cloud(write_file("rgb0.las", make_las(spec_with_points(2, 3, 2))));
  EXPECT_FALSE(dz.has("colors"));
  EXPECT_EQ(md_int(dz, "colors_all_zero"), 1);
}

TEST(IoLasGenerated, AllPointFormatsReadWithStandardLengths) {
  const int lengths[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  for (int pf = 0; pf <= 10; ++pf) {
    SCOPED_TRACE(pf);
    LasSpec s = spec_with_points(4, pf, 5);
    for (auto& p : s.points) p.rgb[0] = 300;
    PointData d = read_point_cloud(write_file("pf" + std::to_string(pf) + ".las", make_las(s)));
    ASSERT_EQ(d.num_points(), 5u);
    EXPECT_EQ(md_int(d, "point_record_length"), lengths[pf]);
    EXPECT_EQ(d.positions[3 * 4 + 1], (-2000 - 4) * 0.01);
    EXPECT_EQ(attr<float>(d, "intensity")[4], 400.f);
    EXPECT_EQ(attr<uint8_t>(d, "classification")[4], 4);
    const bool has_gps = pf != 0 && pf != 2;
    EXPECT_EQ(d.has("gps_time"), has_gps);
    if (has_gps) {
      EXPECT_EQ(attr<double>(d, "gps_time")[4], 6.0);
    }
    const bool has_rgb = pf == 2 || pf == 3 || pf == 5 || pf == 7 || pf == 8 || pf == 10;
    EXPECT_EQ(d.has("colors"), has_rgb);
    EXPECT_EQ(d.has("nir"), pf == 8 || pf == 10);
  }
}

TEST(IoLasGenerated, ManyPointsAcrossParallelBlocks) {
  const size_t n = 200003;  // several decoding blocks, last one partial
  LasSpec s;
  s.version_minor = 4;
  s.point_format = 7;
  s.offset[0] = 500000.0;
  s.points.resize(n);
  for (size_t i = 0; i < n; ++i) {
    LasPoint& p = s.points[i];
    p.x = static_cast<int32_t>(i * 3);
    p.y = -static_cast<int32_t>(i);
    p.z = static_cast<int32_t>(i % 1000);
    p.intensity = static_cast<uint16_t>(i);
    p.classification = static_cast<uint8_t>(i % 256);
    p.gps_time = static_cast<double>(i) * 0.5;
    for (int c = 0; c < 3; ++c) p.rgb[c] = static_cast<uint16_t>((i + c) % 256);
  }
  s.points[n - 1].rgb[2] = 256;  // only the very last value says "16-bit"
  PointData d = read_point_cloud(write_file("many.las", make_las(s)));
  ASSERT_EQ(d.num_points(), n);
  EXPECT_EQ(md_int(d, "color_bits"), 16);
  const auto& cls = attr<uint8_t>(d, "classification");
  const auto& inten = attr<float>(d, "intensity");
  const auto& gps = attr<double>(d, "gps_time");
  const auto& col = attr<uint8_t>(d, "colors");
  size_t bad = 0;
  for (size_t i = 0; i < n; ++i) {
    bad += d.positions[3 * i] != static_cast<double>(i * 3) * 0.01 + 500000.0;
    bad += d.positions[3 * i + 1] != static_cast<double>(-static_cast<int32_t>(i)) * 0.01;
    bad += cls[i] != i % 256;
    bad += inten[i] != static_cast<float>(static_cast<uint16_t>(i));
    bad += gps[i] != static_cast<double>(i) * 0.5;
    bad += col[3 * i] != 0;  // values < 256 in a 16-bit file are dark
  }
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(col[3 * (n - 1) + 2], 1);
}

TEST(IoLasGenerated, RecordLongerThanFormatWithoutDescription) {
  LasSpec s = spec_with_points(2, 3, 2);
  s.record_length = 40;
  for (auto& p : s.points) p.extra = std::string(6, 'x');
  PointData d = read_point_cloud(write_file("padded.las", make_las(s)));
  EXPECT_EQ(d.num_points(), 2u);
  EXPECT_EQ(md_int(d, "extra_bytes_undescribed"), 6);
  EXPECT_EQ(d.positions[3], 1001 * 0.01);
}

TEST(IoLasGenerated, WktInExtendedVlr) {
  LasSpec s = spec_with_points(4, 6, 2);
  s.evlrs.push_back(LasVlr{"LASF_Projection", 2112, std::string("PROJCS[\"test\"]") + '\0'});
  PointData d = read_point_cloud(write_file("evlr_wkt.las", make_las(s)));
  EXPECT_EQ(md_str(d, "crs_wkt"), "PROJCS[\"test\"]");
}

TEST(IoLasGenerated, EmptyPointSetIsValid) {
  PointData d = read_point_cloud(write_file("empty.las", make_las(spec_with_points(2, 3, 0))));
  EXPECT_EQ(d.num_points(), 0u);
}

class IoLasBroken : public ::testing::Test {
 protected:
  std::string good = make_las(spec_with_points(2, 3, 10));
  std::string path(const std::string& name, const std::string& bytes) {
    return write_file(name, bytes);
  }
};

TEST_F(IoLasBroken, EmptyAndForeignFiles) {
  EXPECT_READ_ERROR(path("empty0.las", ""), "file is empty");
  EXPECT_READ_ERROR(path("foreign.las", "PK\x03\x04 this is a zip"), "'LASF' signature");
  EXPECT_READ_ERROR(path("short.las", good.substr(0, 100)), "smaller than the 227-byte LAS header");
  EXPECT_READ_ERROR(data_path("does_not_exist.las"), "cannot open file");
}

TEST_F(IoLasBroken, HeaderFields) {
  std::string b = good;
  b[24] = 2;
  EXPECT_READ_ERROR(path("v2.las", b), "unsupported LAS version 2.2");
  b = good;
  test_io::poke<uint16_t>(b, 94, 200);
  EXPECT_READ_ERROR(path("hs.las", b), "header size 200 is smaller than the 227 bytes");
  b = good;
  test_io::poke<uint32_t>(b, 96, 100);
  EXPECT_READ_ERROR(path("off_in_header.las", b), "lies inside the header");
  b = good;
  test_io::poke<uint32_t>(b, 96, 1u << 30);
  EXPECT_READ_ERROR(path("off_past_end.las", b), "beyond the end");
  b = good;
  b[104] = 11;
  EXPECT_READ_ERROR(path("pf11.las", b), "unsupported point data record format 11");
  b = good;
  b[104] = static_cast<char>(0x83);
  EXPECT_READ_ERROR(path("compressed.las", b),
                    "marks the points as compressed, but the file has no LASzip VLR");
  b = good;
  test_io::poke<uint16_t>(b, 105, 20);
  EXPECT_READ_ERROR(path("short_record.las", b),
                    "point record length 20 is smaller than the 34 bytes point format 3 requires");
  b = good;
  test_io::poke<double>(b, 131 + 8, 0.0);
  EXPECT_READ_ERROR(path("scale0.las", b), "scale factor for Y");
}

TEST_F(IoLasBroken, TruncatedPointData) {
  EXPECT_READ_ERROR(path("trunc1.las", good.substr(0, good.size() - 1)),
                    "the header declares 10 points of 34 bytes (340 bytes) starting at byte 227, "
                    "but only 339 bytes follow");
  std::string b = good;
  test_io::poke<uint32_t>(b, 107, 0xFFFFFFFFu);
  EXPECT_READ_ERROR(path("count_huge.las", b), "declares 4294967295 points");
  LasSpec s = spec_with_points(4, 6, 3);
  std::string b14 = make_las(s);
  test_io::poke<uint64_t>(b14, 247, uint64_t{1} << 62);  // absurd 64-bit count, no allocation
  EXPECT_READ_ERROR(path("count64.las", b14), "declares 4611686018427387904 points");
}

TEST_F(IoLasBroken, Vlrs) {
  LasSpec s = spec_with_points(2, 3, 2);
  s.vlrs.push_back(LasVlr{"someone", 1, std::string(40, 'v')});
  const std::string with_vlr = make_las(s);
  std::string b = with_vlr;
  test_io::poke<uint32_t>(b, 100, 0x7FFFFFFF);
  EXPECT_READ_ERROR(path("vlr_count.las", b), "header declares 2147483647 variable length records");
  b = with_vlr;
  test_io::poke<uint16_t>(b, 227 + 20, 41);  // one byte too long
  EXPECT_READ_ERROR(path("vlr_len.las", b), "is 41 bytes long and would run past the start of the point data");
  // Extra bytes VLR describing more than the records hold.
  LasSpec e = spec_with_points(4, 6, 2);
  e.vlrs.push_back(LasVlr{"LASF_Spec", 4, test_io::extra_bytes_descriptor("big", 10, false)});
  for (auto& p : e.points) p.extra = std::string(4, '\0');
  EXPECT_READ_ERROR(path("eb_big.las", make_las(e)), "describes 8 bytes per point");
  e.vlrs[0].payload.resize(100);
  EXPECT_READ_ERROR(path("eb_len.las", make_las(e)), "not a multiple of the 192-byte");
  // A leftover laszip VLR in a file whose points are uncompressed is ignored.
  LasSpec z = spec_with_points(2, 3, 1);
  z.vlrs.push_back(LasVlr{"laszip encoded", 22204, std::string(52, '\0')});
  EXPECT_EQ(read_las(path("laszip_vlr.las", make_las(z))).num_points(), 1u);
  // Compressed points with that (empty) VLR: compressor 0 is not LASzip's.
  std::string zc = make_las(z);
  zc[104] = static_cast<char>(0x83);
  EXPECT_READ_ERROR(path("laszip_vlr0.laz", zc), "LAZ file uses compressor 0");
}

TEST_F(IoLasBroken, ExtendedVlrsPastEnd) {
  LasSpec s = spec_with_points(4, 6, 2);
  s.evlrs.push_back(LasVlr{"LASF_Projection", 2112, "PROJCS[]"});
  std::string b = make_las(s);
  std::string cut = b.substr(0, b.size() - 3);
  EXPECT_READ_ERROR(path("evlr_trunc.las", cut), "more than remain in the file");
  test_io::poke<uint32_t>(b, 243, 1000000);
  EXPECT_READ_ERROR(path("evlr_count.las", b), "header declares 1000000 extended VLRs");
}

TEST(IoDispatch, ExtensionAndSignature) {
  const std::string las = make_las(spec_with_points(2, 0, 2));
  PointData d = read_point_cloud(write_file("no_extension", las));
  EXPECT_EQ(d.num_points(), 2u);
  EXPECT_EQ(md_str(d, "format"), "las");
  EXPECT_READ_ERROR(write_file("mystery.bin", "hello world"), "unrecognised point cloud format (extension '.bin')");
  // The extension does not decide: uncompressed points in a .LAZ are read as LAS.
  EXPECT_EQ(read_point_cloud(write_file("upper.LAZ", las)).num_points(), 2u);
}

}  // namespace
}  // namespace pointnpr

namespace pointnpr {

namespace {
size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  size_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * size_t(::sysconf(_SC_PAGESIZE));
}
}  // namespace

TEST(IoMappedFile, ReleasedPagesLeaveTheResidentSetAndReadTheSameAgain) {
  // Larger than the populate limit: mapped lazily, touched here, released.
  const auto path = test_io::scratch_path() / "release.bin";
  std::filesystem::create_directories(path.parent_path());
  const size_t size = size_t{96} << 20;
  {
    std::vector<uint8_t> bytes(size);
    for (size_t i = 0; i < size; ++i) bytes[i] = uint8_t(i * 2654435761u >> 13);
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(size));
  }
  io::MappedFile file(path.string());
  ASSERT_EQ(file.size(), size);
  uint64_t sum = 0;
  for (size_t i = 0; i < size; i += 512) sum += file.data()[i];
  const size_t touched = resident_bytes();
  file.release(0, size);
  const size_t released = resident_bytes();
  EXPECT_GT(touched, released + size * 9 / 10) << "touched " << touched << ", after release " << released;
  uint64_t again = 0;
  for (size_t i = 0; i < size; i += 512) again += file.data()[i];
  EXPECT_EQ(again, sum);
  for (size_t i : {size_t(0), size_t(4095), size_t(4096), size / 2 + 7, size - 1})
    EXPECT_EQ(file.data()[i], uint8_t(i * 2654435761u >> 13));
  std::filesystem::remove(path);
}

TEST(IoLas, FileReadReleasingItsBlocksGivesTheBytesReadersPoints) {
  // 110,000 points: two decode blocks, released as they are read; the
  // in-memory reader (nothing released) is the reference, point by point.
  const std::string path = data_path("autzen_trim.las");
  std::ifstream f(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), {});
  const PointData from_file = read_point_cloud(path);
  const PointData from_memory = read_las_memory(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), path);
  ASSERT_EQ(from_file.num_points(), 110000u);
  EXPECT_EQ(from_file.positions, from_memory.positions);
  ASSERT_EQ(from_file.attributes.size(), from_memory.attributes.size());
  for (size_t a = 0; a < from_file.attributes.size(); ++a) {
    EXPECT_EQ(from_file.attributes[a].name, from_memory.attributes[a].name);
    EXPECT_TRUE(from_file.attributes[a].values == from_memory.attributes[a].values) << from_file.attributes[a].name;
  }
}

}  // namespace pointnpr
