// PCD and delimited-text readers: PCL/PDAL test files, an organized LZF crop
// of a Kinect frame, and generated files for each encoding and failure.
#include <bit>
#include <cmath>

#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::attr;
using test_io::Bytes;
using test_io::data_path;
using test_io::write_file;

int64_t md_int(const PointData& d, const std::string& key) { return std::get<int64_t>(d.metadata.at(key)); }

// ----------------------------------------------------------------------- PCD

TEST(IoPcd, OrganizedLzfCropDropsNaN) {
  PointData d = read_point_cloud(data_path("mug_crop.pcd"));
  EXPECT_EQ(md_int(d, "width"), 80);
  EXPECT_EQ(md_int(d, "height"), 60);
  EXPECT_EQ(md_int(d, "organized"), 1);
  EXPECT_EQ(md_int(d, "point_count"), 4800);
  ASSERT_EQ(d.num_points(), 4749u);
  EXPECT_EQ(md_int(d, "dropped_nonfinite"), 51);
  EXPECT_EQ(d.positions[0], -0.06441300362348557);
  EXPECT_EQ(d.positions[1], -0.04670400172472);
  EXPECT_EQ(d.positions[2], 1.038599967956543);
  EXPECT_EQ(d.positions[3 * 4748 + 0], 0.014983000233769417);
  EXPECT_EQ(d.positions[3 * 4748 + 2], 0.752810001373291);
  const auto& c = attr<uint8_t>(d, "colors");
  EXPECT_EQ(c[0], 245);
  EXPECT_EQ(c[1], 246);
  EXPECT_EQ(c[2], 39);
  EXPECT_EQ(c[3 * 4748 + 0], 248);
  EXPECT_EQ(c[3 * 4748 + 2], 81);
}

TEST(IoPcd, PclAndPdalFiles) {
  PointData bin = read_point_cloud(data_path("malformed/pcd_pcl_colored_cloud_binary_h1000.pcd"));
  ASSERT_EQ(bin.num_points(), 1000u);
  EXPECT_EQ(bin.positions[0], -0.8550515174865723);
  EXPECT_EQ(bin.positions[3 * 999 + 2], 0.9129999876022339);
  EXPECT_EQ(attr<uint8_t>(bin, "colors")[0], 0x6c);
  EXPECT_EQ(attr<uint8_t>(bin, "colors")[1], 0x6d);
  EXPECT_EQ(attr<uint8_t>(bin, "colors")[2], 0x69);
  EXPECT_EQ(attr<float>(bin, "normals")[0], 0.6966168880462646f);
  EXPECT_EQ(attr<float>(bin, "curvature")[0], 0.052542801946401596f);

  PointData ascii = read_point_cloud(data_path("malformed/pcd_pcl_bun0_normals_ascii.pcd"));
  ASSERT_EQ(ascii.num_points(), 397u);
  EXPECT_EQ(ascii.positions[0], 0.0054215998);
  EXPECT_EQ(ascii.positions[3 * 396 + 1], 0.17516001);
  EXPECT_EQ(attr<float>(ascii, "normals")[3 * 396 + 2], -0.48764735f);

  PointData upper = read_point_cloud(data_path("malformed/pcd_pdal_utm17_space.pcd"));
  ASSERT_EQ(upper.num_points(), 10u);  // fields named X Y Z
  EXPECT_EQ(upper.positions[0], 289814.15);

  EXPECT_READ_ERROR(data_path("malformed/pcd_pdal_missingheader.pcd"),
                    "the PCD header is missing or incomplete");
}

std::string pcd_header(const std::string& fields, const std::string& sizes, const std::string& types,
                       int w, int h, const std::string& data) {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes + "\nTYPE " + types +
         "\nCOUNT" + std::string(std::count(fields.begin(), fields.end(), ' ') + 1, ' ') + "\n" +
         "WIDTH " + std::to_string(w) + "\nHEIGHT " + std::to_string(h) +
         "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(w * h) + "\nDATA " + data + "\n";
}

std::string pcd_header_simple(int w, int h, const std::string& data) {
  return "VERSION .7\nFIELDS x y z rgb label\nSIZE 4 4 8 4 2\nTYPE F F F F U\nCOUNT 1 1 1 1 1\nWIDTH " +
         std::to_string(w) + "\nHEIGHT " + std::to_string(h) + "\nPOINTS " + std::to_string(w * h) +
         "\nDATA " + data + "\n";
}

// Colour packed in a float's bits, as PCL's "rgb" field.
float packed(uint8_t r, uint8_t g, uint8_t b) {
  return std::bit_cast<float>(uint32_t{0xFF000000u} | (uint32_t{r} << 16) | (uint32_t{g} << 8) | b);
}

TEST(IoPcdGenerated, AsciiBinaryAndCompressedAgree) {
  const float nanf = std::nanf("");
  struct P {
    float x, y;
    double z;
    float rgb;
    uint16_t label;
  };
  const P pts[4] = {{1.5f, -2.f, 1e6 + 0.125, packed(10, 20, 30), 7},
                    {nanf, nanf, std::nan(""), packed(0, 0, 0), 0},
                    {3.f, 4.f, -5.0, packed(255, 128, 1), 65535},
                    {0.25f, 0.5f, 0.75, packed(1, 2, 3), 3}};
  // ascii: the packed colour written as an unsigned integer (PCL does this:
  // opaque colours with red >= 128 are NaN as floats).
  std::string ascii = pcd_header_simple(2, 2, "ascii");
  for (const P& p : pts) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "%.9g %.9g %.17g %u %u\n", static_cast<double>(p.x),
                  static_cast<double>(p.y), p.z, std::bit_cast<uint32_t>(p.rgb), p.label);
    ascii += buf;
  }
  // binary: point-major records.
  Bytes bin;
  bin.raw(pcd_header_simple(2, 2, "binary"));
  for (const P& p : pts) bin.put(p.x).put(p.y).put(p.z).put(p.rgb).put(p.label);
  // binary_compressed: field-major, LZF of literal runs only.
  Bytes soa;
  for (const P& p : pts) soa.put(p.x);
  for (const P& p : pts) soa.put(p.y);
  for (const P& p : pts) soa.put(p.z);
  for (const P& p : pts) soa.put(p.rgb);
  for (const P& p : pts) soa.put(p.label);
  std::string lzf;
  for (size_t i = 0; i < soa.s.size(); i += 32) {
    const size_t len = std::min<size_t>(32, soa.s.size() - i);
    lzf += static_cast<char>(len - 1);
    lzf += soa.s.substr(i, len);
  }
  Bytes comp;
  comp.raw(pcd_header_simple(2, 2, "binary_compressed"))
      .put<uint32_t>(static_cast<uint32_t>(lzf.size()))
      .put<uint32_t>(static_cast<uint32_t>(soa.s.size()))
      .raw(lzf);
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"gen_ascii.pcd", ascii}, {"gen_bin.pcd", bin.s}, {"gen_comp.pcd", comp.s}}) {
    SCOPED_TRACE(name);
    PointData d = read_point_cloud(write_file(name, bytes));
    ASSERT_EQ(d.num_points(), 3u);
    EXPECT_EQ(md_int(d, "dropped_nonfinite"), 1);
    EXPECT_EQ(d.positions, (std::vector<double>{1.5, -2, 1e6 + 0.125, 3, 4, -5, 0.25, 0.5, 0.75}));
    EXPECT_EQ(attr<uint8_t>(d, "colors"), (std::vector<uint8_t>{10, 20, 30, 255, 128, 1, 1, 2, 3}));
    EXPECT_EQ(attr<float>(d, "label"), (std::vector<float>{7, 65535, 3}));
  }
}

TEST(IoPcdGenerated, AsciiColourFormats) {
  const std::string h = "VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 3\nHEIGHT 1\n"
                        "POINTS 3\nDATA ascii\n";
  // Integer, float-formatted integer (older PCL; 0x404040 = 4210752) and a
  // float whose bits carry the colour (0x00102030 as a denormal).
  char denormal[64];
  std::snprintf(denormal, sizeof denormal, "%.9g",
                static_cast<double>(std::bit_cast<float>(uint32_t{0x00102030})));
  PointData d = read_point_cloud(write_file(
      "rgb_ascii.pcd", h + "0 0 0 16711680\n1 1 1 4.210752e+06\n2 2 2 " + denormal + "\n"));
  EXPECT_EQ(attr<uint8_t>(d, "colors"), (std::vector<uint8_t>{255, 0, 0, 64, 64, 64, 16, 32, 48}));
}

TEST(IoPcdBroken, HeadersAndData) {
  const std::string h = pcd_header("x y z", "4 4 4", "F F F", 4, 1, "binary");
  EXPECT_READ_ERROR(write_file("p1.pcd", h + std::string(47, '\0')),
                    "the header declares 4 points of 12 bytes, but only 47 bytes");
  EXPECT_READ_ERROR(write_file("p2.pcd", pcd_header("x y", "4 4", "F F", 1, 1, "binary") + std::string(8, '\0')),
                    "no 'z' field");
  EXPECT_READ_ERROR(write_file("p3.pcd", pcd_header("x y z", "4 4", "F F F", 1, 1, "binary")),
                    "list different numbers of entries");
  EXPECT_READ_ERROR(write_file("p4.pcd", pcd_header("x y z", "4 4 3", "F F F", 1, 1, "binary")),
                    "invalid SIZE '3'");
  EXPECT_READ_ERROR(write_file("p5.pcd", pcd_header("x y z", "4 4 4", "F F F", 1, 1, "lzma")),
                    "unknown PCD DATA kind 'lzma'");
  EXPECT_READ_ERROR(write_file("p6.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 5\nDATA ascii\n"),
                    "WIDTH 2 x HEIGHT 2 != POINTS 5");
  EXPECT_READ_ERROR(write_file("p7.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n"),
                    "no DATA line");
  EXPECT_READ_ERROR(write_file("p8.pcd", pcd_header("x y z", "4 4 4", "F F F", 2, 1, "ascii") + "1 2 3\n4 5 six\n"),
                    "invalid value 'six' for field 'z' of point 1");
  EXPECT_READ_ERROR(write_file("p9.pcd", pcd_header("x y z", "4 4 4", "F F F", 2, 1, "ascii") + "1 2 3\n4.0 5.0\n"),
                    "the data ends after 1 of 2 points");
  // Absurd point count: refused before allocating.
  const std::string huge = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000000000000\n"
                           "HEIGHT 1\nPOINTS 1000000000000\nDATA binary\n";
  EXPECT_READ_ERROR(write_file("p10.pcd", huge + std::string(12, '\0')), "declares 1000000000000 points");
  // Compressed: sizes inconsistent with POINTS, impossible expansion, corrupt back-reference.
  const std::string hc = pcd_header("x y z", "4 4 4", "F F F", 1, 1, "binary_compressed");
  Bytes c1;
  c1.raw(hc).put<uint32_t>(2).put<uint32_t>(24).raw("ab");
  EXPECT_READ_ERROR(write_file("c1.pcd", c1.s), "decompresses to 24 bytes, but POINTS x record size is 12");
  const std::string hbig = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 100000000\nHEIGHT 1\n"
                           "POINTS 100000000\nDATA binary_compressed\n";
  Bytes c2;
  c2.raw(hbig).put<uint32_t>(2).put<uint32_t>(1200000000u).raw("ab");
  EXPECT_READ_ERROR(write_file("c2.pcd", c2.s), "more than 2 LZF bytes can hold");
  Bytes c3;
  c3.raw(hc).put<uint32_t>(3).put<uint32_t>(12).put<uint8_t>(0xE0).put<uint8_t>(3).put<uint8_t>(0);
  EXPECT_READ_ERROR(write_file("c3.pcd", c3.s), "back-reference before the start of the output");
  Bytes c4;
  c4.raw(hc).put<uint32_t>(4).put<uint32_t>(12).put<uint8_t>(2).raw("abc");
  EXPECT_READ_ERROR(write_file("c4.pcd", c4.s), "decompressed to 3 bytes, the header declares 12");
  Bytes c5;
  c5.raw(hc).put<uint32_t>(100).put<uint32_t>(12).raw("abc");
  EXPECT_READ_ERROR(write_file("c5.pcd", c5.s), "100 compressed bytes declared, 3 present");
}

// ---------------------------------------------------------------------- text

TEST(IoText, PdalAndCloudCompareFiles) {
  PointData crlf = read_point_cloud(data_path("malformed/text_pdal_crlf_test.txt"));
  ASSERT_EQ(crlf.num_points(), 10u);
  EXPECT_EQ(crlf.positions[0], 289814.15);
  EXPECT_EQ(crlf.positions[3 * 9 + 1], 4320980.59);
  EXPECT_EQ(attr<float>(crlf, "intensity")[9], 9.f);

  PointData quoted = read_point_cloud(data_path("malformed/text_pdal_quoted.txt"));
  ASSERT_EQ(quoted.num_points(), 9u);
  EXPECT_EQ(quoted.positions[3 * 8 + 0], 29.0);

  PointData cc = read_point_cloud(data_path("malformed/text_trimesh_points_cloudcompare.xyz"));
  ASSERT_EQ(cc.num_points(), 101u);
  EXPECT_EQ(cc.positions[3], 665187.404645);
  EXPECT_EQ(cc.positions[5], 244.857091);
  EXPECT_EQ(attr<uint8_t>(cc, "colors")[3], 91);
  EXPECT_EQ(attr<uint8_t>(cc, "colors")[5], 74);
}

TEST(IoTextGenerated, LayoutsAndHeaders) {
  PointData pts = read_point_cloud(write_file("leica.pts", "2\n1 2 3 -1200 10 20 30\n4 5 6 300 40 50 60\n"));
  ASSERT_EQ(pts.num_points(), 2u);
  EXPECT_EQ(attr<float>(pts, "intensity"), (std::vector<float>{-1200, 300}));
  EXPECT_EQ(attr<uint8_t>(pts, "colors"), (std::vector<uint8_t>{10, 20, 30, 40, 50, 60}));

  PointData nrm = read_point_cloud(write_file("normals.xyz", "1 2 3 0 0 1\n4 5 6 0.6 0.8 0\n"));
  EXPECT_EQ(attr<float>(nrm, "normals"), (std::vector<float>{0, 0, 1, 0.6f, 0.8f, 0}));

  PointData cc = read_point_cloud(write_file("cc.txt", "//X;Y;Z;R;G;B;Classification\n"
                                                       "1;2;3;0.5;1;0;6\n# comment\n\n4;5;6;0;0;1;2\n"));
  EXPECT_EQ(attr<uint8_t>(cc, "colors"), (std::vector<uint8_t>{128, 255, 0, 0, 0, 255}));
  EXPECT_EQ(attr<uint8_t>(cc, "classification"), (std::vector<uint8_t>{6, 2}));

  PointData named = read_point_cloud(write_file("named.csv", "z,y,x,temperature\r\n3,2,1,20.5\r\n"));
  EXPECT_EQ(named.positions, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(attr<float>(named, "temperature")[0], 20.5f);

  EXPECT_READ_ERROR(write_file("t1.xyz", "1 2 3\n4 5\n"), "line 2 has 2 values, expected 3");
  EXPECT_READ_ERROR(write_file("t2.xyz", "1 2 3\n4 5 x\n"), "line 2: 'x' is not a number");
  EXPECT_READ_ERROR(write_file("t3.xyz", "a b c\n"), "contains no points");
  EXPECT_READ_ERROR(write_file("t4.csv", "a,b,c\n1,2,3\n"), "no 'x' column");
  EXPECT_READ_ERROR(write_file("t5.xyz", "1 2\n3 4\n"), "a point needs at least x, y and z");
  EXPECT_READ_ERROR(write_file("t6.xyz", ""), "file is empty");
}

}  // namespace
}  // namespace pointnpr
