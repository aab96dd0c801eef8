// PLY reader: real scans, other projects' test files, and generated files in
// all three encodings (big-endian, CRLF ascii, lists, elements around the
// vertex element) plus broken headers and truncated data.
#include <cmath>

#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::attr;
using test_io::Bytes;
using test_io::data_path;
using test_io::write_file;

// ---------------------------------------------------------------- real scans

TEST(IoPly, BunnyAsciiMesh) {
  PointData d = read_point_cloud(data_path("bun_zipper_res2.ply"));
  ASSERT_EQ(d.num_points(), 8171u);
  EXPECT_EQ(std::get<std::string>(d.metadata.at("format")), "ply");
  EXPECT_EQ(std::get<std::string>(d.metadata.at("encoding")), "ascii");
  EXPECT_EQ(d.positions[0], -0.036872);
  EXPECT_EQ(d.positions[1], 0.127727);
  EXPECT_EQ(d.positions[2], 0.00440925);
  EXPECT_EQ(d.positions[3 * 8170 + 0], -0.0318636);
  EXPECT_EQ(d.positions[3 * 8170 + 2], -0.00893878);
  EXPECT_EQ(attr<float>(d, "confidence")[0], 0.850855f);
  EXPECT_EQ(attr<float>(d, "intensity")[0], 0.5f);
  EXPECT_FALSE(d.has("colors"));
}

TEST(IoPly, ElephantBinaryWithTristrips) {
  PointData d = read_point_cloud(data_path("tinyply_elephant.ply"));
  ASSERT_EQ(d.num_points(), 19753u);
  EXPECT_EQ(d.positions[0], -1.0163400173187256);
  EXPECT_EQ(d.positions[1], 13.204500198364258);
  EXPECT_EQ(d.positions[2], -14.426400184631348);
  EXPECT_EQ(d.positions[3 * 19752 + 0], -3.62391996383667);
  EXPECT_EQ(d.positions[3 * 19752 + 2], 10.771699905395508);
  EXPECT_FALSE(d.metadata.count("trailing_bytes"));  // the tristrips were walked exactly
}

// ------------------------------------------------- other projects' test files

TEST(IoPly, ValidOddFiles) {
  struct Case {
    const char* file;
    size_t points;
    double x0;
  };
  const Case cases[] = {
      {"malformed/ply_assimp_cube.ply", 8, 0.0},
      {"malformed/ply_assimp_cube_binary_header_with_RN_newline.ply", 8, 0.0},
      {"malformed/ply_assimp_float-color.ply", 3, 0.0},
      {"malformed/ply_assimp_malformed_face_texcoord_oob.ply", 3, 0.0},
      {"malformed/ply_assimp_points.ply", 4, 0.0},
      {"malformed/ply_pdal_issue_2421.ply", 1, 1.23457},
      {"malformed/ply_pdal_mesh_fixed.ply", 4, 1.0},
      {"malformed/ply_pdal_simple_binary.ply", 3, -1.0},
      {"malformed/ply_tinyply_sofa.ply", 12103, -1023.3244018554688},
      {"malformed/ply_trimesh_emptyIO_ply_points_bin.ply", 8, 1.0},
      {"malformed/ply_trimesh_points_ascii.ply", 5, -0.06325},
      {"malformed/ply_trimesh_points_bin.ply", 5, static_cast<double>(-0.06325f)},
      {"malformed/ply_trimesh_points_emptyface.ply", 1024, -86.01312256},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    PointData d = read_point_cloud(data_path(c.file));
    ASSERT_EQ(d.num_points(), c.points);
    EXPECT_EQ(d.positions[0], c.x0);
  }
}

TEST(IoPly, DetailsOfOddFiles) {
  PointData fc = read_point_cloud(data_path("malformed/ply_assimp_float-color.ply"));
  EXPECT_EQ(attr<uint8_t>(fc, "colors"), (std::vector<uint8_t>{0, 0, 255, 0, 0, 255, 0, 0, 255}));
  EXPECT_EQ(attr<uint8_t>(fc, "alpha"), (std::vector<uint8_t>{255, 255, 255}));
  EXPECT_EQ(fc.positions[3 * 2 + 1], 200.0);

  PointData pts = read_point_cloud(data_path("malformed/ply_assimp_points.ply"));
  EXPECT_EQ(attr<uint8_t>(pts, "colors")[3 * 1 + 1], 0);
  EXPECT_EQ(attr<uint8_t>(pts, "colors")[3 * 1 + 2], 255);
  const PointAttribute* n = pts.find("normals");
  ASSERT_NE(n, nullptr);
  EXPECT_EQ(n->components, 3);
  EXPECT_EQ(attr<float>(pts, "normals"), (std::vector<float>{0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 1, 0}));

  PointData big = read_point_cloud(data_path("malformed/ply_pdal_issue_2421.ply"));
  EXPECT_EQ(big.positions[1], 12345.6789);
  EXPECT_EQ(big.positions[2], 1234567890.12345);  // float64 property keeps full precision
  EXPECT_EQ(attr<int32_t>(big, "i")[0], 1234567890);  // keeps its int32 type

  PointData sofa = read_point_cloud(data_path("malformed/ply_tinyply_sofa.ply"));
  EXPECT_EQ(attr<uint8_t>(sofa, "colors")[0], 192);
  EXPECT_EQ(attr<uint8_t>(sofa, "alpha")[0], 255);

  PointData empty = read_point_cloud(data_path("malformed/ply_trimesh_emptyIO_ply_empty_ascii.ply"));
  EXPECT_EQ(empty.num_points(), 0u);

  PointData bin = read_point_cloud(data_path("malformed/ply_trimesh_emptyIO_ply_points_bin.ply"));
  EXPECT_EQ(attr<float>(bin, "normals").size(), 24u);
}

TEST(IoPly, BrokenFilesAreRefused) {
  EXPECT_READ_ERROR(data_path("malformed/ply_pdal_sized_dims.ply"), "vertex element has no 'z' property");
  EXPECT_READ_ERROR(data_path("malformed/ply_pdal_unsized_dims.ply"), "vertex element has no 'z' property");
  EXPECT_READ_ERROR(data_path("malformed/ply_trimesh_emptyIO_ply_empty_header.ply"),
                    "the file has no 'vertex' element");
}

// ------------------------------------------------------------ generated files

// Header with one vertex element of all scalar types, then a face element
// with a list, then a custom element with two lists.
std::string typed_header(const std::string& format, const std::string& eol) {
  std::string h = "ply" + eol + "format " + format + " 1.0" + eol + "comment generated" + eol +
                  "obj_info by test_io_ply" + eol + "element vertex 2" + eol;
  const char* props[] = {"double x", "float y",      "int z",         "char c8",  "uchar u8",
                         "short s16", "ushort u16", "uint u32",      "float32 nx", "float32 ny",
                         "float32 nz", "uint8 red",  "uint8 green",   "uint8 blue"};
  for (const char* p : props) h += std::string("property ") + p + eol;
  h += "element face 2" + eol + "property list uchar int vertex_indices" + eol;
  h += "element extra 1" + eol + "property list ushort float a" + eol + "property short k" + eol +
       "property list int8 uint16 b" + eol;
  h += "end_header" + eol;
  return h;
}

struct Vtx {
  double x;
  float y;
  int32_t z;
  int8_t c8;
  uint8_t u8;
  int16_t s16;
  uint16_t u16;
  uint32_t u32;
  float n[3];
  uint8_t rgb[3];
};
const Vtx kVerts[2] = {
    {6617080.123456789, -1.5f, -7, -128, 255, -32768, 65535, 4000000000u, {0, 0, 1}, {10, 20, 30}},
    {-0.25, 1e-3f, 2147483647, 127, 0, 32767, 0, 0, {1, 0, 0}, {255, 0, 128}},
};

template <bool BE>
std::string binary_ply() {
  Bytes b;
  b.raw(typed_header(BE ? "binary_big_endian" : "binary_little_endian", "\n"));
  auto put = [&](auto v) {
    if constexpr (BE)
      b.put_be(v);
    else
      b.put(v);
  };
  for (const Vtx& v : kVerts) {
    put(v.x), put(v.y), put(v.z), put(v.c8), put(v.u8), put(v.s16), put(v.u16), put(v.u32);
    put(v.n[0]), put(v.n[1]), put(v.n[2]), put(v.rgb[0]), put(v.rgb[1]), put(v.rgb[2]);
  }
  put(uint8_t{3}), put(int32_t{0}), put(int32_t{1}), put(int32_t{0});
  put(uint8_t{0});
  put(uint16_t{2}), put(1.f), put(2.f), put(int16_t{-1}), put(int8_t{1}), put(uint16_t{9});
  return b.s;
}

std::string ascii_ply(const std::string& eol) {
  std::string s = typed_header("ascii", eol);
  s += "6617080.123456789 -1.5 -7 -128 255 -32768 65535 4000000000 0 0 1 10 20 30" + eol;
  s += "-0.25 0.001 2147483647 127 0 32767 0 0 1 0 0 255 0 128" + eol;
  s += "3 0 1 0" + eol + "0" + eol + "2 1 2 -1 1 9" + eol;
  return s;
}

void expect_typed(const PointData& d, bool ascii) {
  ASSERT_EQ(d.num_points(), 2u);
  for (int i = 0; i < 2; ++i) {
    const Vtx& v = kVerts[i];
    EXPECT_EQ(d.positions[3 * i + 0], v.x);
    // ascii keeps the decimal text's double value; binary the float's.
    EXPECT_EQ(d.positions[3 * i + 1], ascii && i == 1 ? 0.001 : static_cast<double>(v.y));
    EXPECT_EQ(d.positions[3 * i + 2], static_cast<double>(v.z));
    // Other properties keep their declared type.
    EXPECT_EQ(attr<int8_t>(d, "c8")[i], v.c8);
    EXPECT_EQ(attr<uint8_t>(d, "u8")[i], v.u8);
    EXPECT_EQ(attr<int16_t>(d, "s16")[i], v.s16);
    EXPECT_EQ(attr<uint16_t>(d, "u16")[i], v.u16);
    EXPECT_EQ(attr<uint32_t>(d, "u32")[i], v.u32);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(attr<float>(d, "normals")[3 * i + c], v.n[c]);
      EXPECT_EQ(attr<uint8_t>(d, "colors")[3 * i + c], v.rgb[c]);
    }
  }
  EXPECT_EQ(std::get<std::string>(d.metadata.at("elements")), "vertex face extra");
  EXPECT_FALSE(d.metadata.count("trailing_bytes"));
}

TEST(IoPlyGenerated, BinaryLittleEndian) {
  expect_typed(read_point_cloud(write_file("typed_le.ply", binary_ply<false>())), false);
}

TEST(IoPlyGenerated, BinaryBigEndian) {
  PointData d = read_point_cloud(write_file("typed_be.ply", binary_ply<true>()));
  EXPECT_EQ(std::get<std::string>(d.metadata.at("encoding")), "binary_big_endian");
  expect_typed(d, false);
}

TEST(IoPlyGenerated, AsciiLfAndCrlf) {
  expect_typed(read_point_cloud(write_file("typed_lf.ply", ascii_ply("\n"))), true);
  expect_typed(read_point_cloud(write_file("typed_crlf.ply", ascii_ply("\r\n"))), true);
}

TEST(IoPlyGenerated, BinaryWithCrlfHeader) {
  std::string s = binary_ply<false>();
  std::string crlf;
  const size_t end = s.find("end_header\n") + 11;
  for (size_t i = 0; i < end; ++i) {
    if (s[i] == '\n') crlf += '\r';
    crlf += s[i];
  }
  expect_typed(read_point_cloud(write_file("typed_crlf_bin.ply", crlf + s.substr(end))), false);
}

TEST(IoPlyGenerated, VertexAfterOtherElementsAndListsInVertex) {
  for (bool ascii : {false, true}) {
    SCOPED_TRACE(ascii);
    std::string h = std::string("ply\nformat ") + (ascii ? "ascii" : "binary_little_endian") +
                    " 1.0\nelement face 2\nproperty list uchar int vertex_indices\n"
                    "element vertex 2\nproperty float x\nproperty list uchar float tex\n"
                    "property float y\nproperty float z\nend_header\n";
    Bytes b;
    b.raw(h);
    if (ascii) {
      b.raw("3 0 1 1\n0\n1 2 0.5 0.25 2 3\n4 0 5 6\n");
    } else {
      b.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(1).put<uint8_t>(0);
      b.put<float>(1).put<uint8_t>(2).put<float>(.5f).put<float>(.25f).put<float>(2).put<float>(3);
      b.put<float>(4).put<uint8_t>(0).put<float>(5).put<float>(6);
    }
    PointData d = read_point_cloud(write_file(ascii ? "after_a.ply" : "after_b.ply", b.s));
    EXPECT_EQ(d.positions, (std::vector<double>{1, 2, 3, 4, 5, 6}));
    EXPECT_FALSE(d.has("tex"));
  }
}

TEST(IoPlyGenerated, ColourRangesAndFloats) {
  const std::string h =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty ushort red\nproperty ushort green\nproperty ushort blue\n"
      "property double alpha\nproperty float scalar_intensity\nproperty uchar classification\n"
      "end_header\n";
  PointData d = read_point_cloud(
      write_file("colour16.ply", h + "0 0 0 65535 0 32896 1 5 2\n1 1 1 257 514 0 0.5 6 9\n"));
  EXPECT_EQ(attr<uint8_t>(d, "colors"), (std::vector<uint8_t>{255, 0, 128, 1, 2, 0}));
  EXPECT_EQ(attr<uint8_t>(d, "alpha"), (std::vector<uint8_t>{255, 128}));
  EXPECT_EQ(attr<float>(d, "intensity"), (std::vector<float>{5, 6}));
  EXPECT_EQ(attr<uint8_t>(d, "classification"), (std::vector<uint8_t>{2, 9}));
}

TEST(IoPlyGenerated, NonFinitePositionsDropped) {
  const std::string s =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "end_header\n1 2 3 1 1 1\nnan 0 0 2 2 2\n4 5 6 3 3 3\n";
  PointData d = read_point_cloud(write_file("nan.ply", s));
  EXPECT_EQ(d.positions, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(attr<uint8_t>(d, "colors"), (std::vector<uint8_t>{1, 1, 1, 3, 3, 3}));
  EXPECT_EQ(std::get<int64_t>(d.metadata.at("dropped_nonfinite")), 1);
}

TEST(IoPlyBroken, Headers) {
  const std::string v = "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n";
  EXPECT_READ_ERROR(write_file("h0.ply", ""), "file is empty");
  EXPECT_READ_ERROR(write_file("h1.ply", "plx\nformat ascii 1.0\n"), "not a PLY file");
  EXPECT_READ_ERROR(write_file("h2.ply", "ply\nformat ascii 1.0\n" + v), "no 'end_header' line");
  EXPECT_READ_ERROR(write_file("h2b.ply", "ply\nformat ascii 1.0\n" + v + "0 0 0\n"),
                    "unexpected header line '0 0 0'");
  EXPECT_READ_ERROR(write_file("h3.ply", "ply\nformat binary_middle_endian 1.0\n" + v + "end_header\n"),
                    "unknown PLY format 'binary_middle_endian'");
  EXPECT_READ_ERROR(write_file("h4.ply", "ply\nformat ascii 1.0\nproperty float x\n" + v + "end_header\n"),
                    "property declared before any element");
  EXPECT_READ_ERROR(write_file("h5.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n"),
                    "unknown property type 'float128'");
  EXPECT_READ_ERROR(write_file("h6.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n"),
                    "invalid count '-1'");
  EXPECT_READ_ERROR(write_file("h7.ply", "ply\n" + v + "end_header\n0 0 0\n"), "no 'format' line");
  EXPECT_READ_ERROR(write_file("h8.ply", "ply\nformat ascii 1.0\n" + v + "property int x\nend_header\n"),
                    "property 'x' is declared twice");
  EXPECT_READ_ERROR(write_file("h9.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n"
                                         "property float y\nproperty float z\nend_header\n"),
                    "vertex property 'x' is a list");
  EXPECT_READ_ERROR(write_file("h10.ply", "ply\nformat ascii 1.0\nbogus line\n" + v + "end_header\n"),
                    "unexpected header line 'bogus line'");
  EXPECT_READ_ERROR(write_file("h11.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n"),
                    "list count type 'float' is not an integer type");
}

TEST(IoPlyBroken, TruncatedBinary) {
  std::string s = binary_ply<false>();
  EXPECT_READ_ERROR(write_file("tb1.ply", s.substr(0, s.size() - 1)), "file is truncated");
  const size_t data = s.find("end_header\n") + 11;
  EXPECT_READ_ERROR(write_file("tb2.ply", s.substr(0, data + 10)),
                    "element 'vertex' declares 2 records of 41 bytes, but only 10 bytes remain");
  // Absurd vertex count: refused before allocating.
  std::string huge = "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000000\n"
                     "property float x\nproperty float y\nproperty float z\nend_header\n" +
                     std::string(24, '\0');
  EXPECT_READ_ERROR(write_file("tb3.ply", huge), "declares 1000000000000000 records of 12 bytes");
  // A list length running past the end of the file.
  std::string lst = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\n"
                    "property list uint int vertex_indices\nend_header\n";
  Bytes b;
  b.raw(lst).put<float>(0).put<float>(0).put<float>(0).put<uint32_t>(4000000000u).put<int32_t>(1);
  EXPECT_READ_ERROR(write_file("tb4.ply", b.s), "declares 4000000000 items, more than remain");
  // Negative list length with a signed count type.
  std::string neg = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\n"
                    "property list char int vertex_indices\nend_header\n";
  Bytes n;
  n.raw(neg).put<float>(0).put<float>(0).put<float>(0).put<int8_t>(-1);
  EXPECT_READ_ERROR(write_file("tb5.ply", n.s), "has a negative length");
}

TEST(IoPlyBroken, TruncatedAndInvalidAscii) {
  std::string s = ascii_ply("\n");
  EXPECT_READ_ERROR(write_file("ta1.ply", s.substr(0, s.size() - 4)), "file is truncated");
  const std::string h =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  EXPECT_READ_ERROR(write_file("ta2.ply", h + "0.0 0.0 0.0\n1.0 1.0\n"),
                    "element 'vertex' ends after 1 of 2 records");
  EXPECT_READ_ERROR(write_file("ta3.ply", h + "0 0 0\n1 1x 1\n"), "invalid number '1x' for property 'y' in record 1");
  {
    // More vertex lines than declared (MeshLab/VCG): the declared ones, and a warning.
    const PointData d = read_point_cloud(write_file("ta4.ply", h + "0 0 0\n1 1 1\n2 2 2\n3 3 3\n"));
    EXPECT_EQ(d.num_points(), 2u);
    EXPECT_EQ(d.positions[3], 1.0);
    EXPECT_EQ(std::get<std::string>(d.metadata.at("warning")),
              "ignored 12 bytes (2 lines) after the last element declared in the header");
    EXPECT_EQ(std::get<int64_t>(d.metadata.at("trailing_bytes")), 12);
  }
  const std::string hc =
      "ply\nformat ascii 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 0\n";
  EXPECT_READ_ERROR(write_file("ta5.ply", hc), "declares 1000000 records of 3 values");
}

TEST(IoPlyBroken, IntegerPropertiesHoldIntegersInRange) {
  const std::string h =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar label\nend_header\n";
  EXPECT_EQ(read_point_cloud(write_file("int1.ply", h + "0 0 0 255\n")).get<uint8_t>("label")->at(0),
            255);
  EXPECT_READ_ERROR(write_file("int2.ply", h + "0 0 0 256\n"),
                    "value '256' of property 'label' in record 0 of element 'vertex' is not an "
                    "integer in the range of its type");
  EXPECT_READ_ERROR(write_file("int3.ply", h + "0 0 0 1.5\n"), "value '1.5' of property 'label'");
  // A float property beyond float's range becomes infinite, not undefined.
  const std::string hf =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty float big\nend_header\n";
  EXPECT_TRUE(std::isinf(read_point_cloud(write_file("big.ply", hf + "0 0 0 1e300\n"))
                             .get<float>("big")
                             ->at(0)));
}

TEST(IoPlyGenerated, ElementsWithoutPropertiesAndHugeCounts) {
  // Found by reasoning about the fuzz targets: an ascii element with no
  // properties has no values, so its count must not be looped over.
  const std::string s =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement junk 18000000000000000000\nend_header\n1 2 3\n";
  PointData d = read_point_cloud(write_file("junk.ply", s));
  EXPECT_EQ(d.num_points(), 1u);
}

TEST(IoPlyLenient, TrailingWhitespaceInTheHeaderIsAccepted) {
  // Writers leave spaces after "ply" and other header lines; other tools read such files.
  const std::string body = "0 0 0\n1 2 3\n";
  for (const char* first : {"ply \n", "ply\t\r\n", "ply  \r\n"}) {
    const std::string s = std::string(first) +
                          "format ascii 1.0 \nelement vertex 2\t\nproperty float x \nproperty float y\n"
                          "property float z  \nend_header \n" + body;
    const PointData d = read_point_cloud(write_file("ws.ply", s));
    ASSERT_EQ(d.num_points(), 2u) << first;
    EXPECT_EQ(d.positions[5], 3.0);
  }
  EXPECT_READ_ERROR(write_file("ws_bad.ply", "plyx\nformat ascii 1.0\n"), "does not start with the line 'ply'");
  EXPECT_READ_ERROR(write_file("ws_bad2.ply", "ply x\nformat ascii 1.0\n"), "does not start with the line 'ply'");
}

}  // namespace
}  // namespace pointnpr
