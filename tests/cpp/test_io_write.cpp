// Writers: write then read gives the same positions (exactly, or within the
// LAS quantisation), attributes and metadata.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/readers.h"
#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::data_path;
using test_io::scratch_dir;

std::string scratch(const std::string& name) { return (scratch_dir() / name).string(); }

double as_double(const PointAttribute& a, size_t k) {
  return std::visit([k](const auto& v) { return static_cast<double>(v[k]); }, a.values);
}

// Every attribute of `a` is in `b` with the same components and values;
// `same_type` also requires the same element type.
// `tolerance` allows a difference for named attributes (LAS scan angle).
void expect_same_attributes(const PointData& a, const PointData& b, bool same_type,
                            const std::map<std::string, double>& tolerance = {}) {
  ASSERT_EQ(a.num_points(), b.num_points());
  for (const PointAttribute& x : a.attributes) {
    const auto tol = tolerance.find(x.name);
    const double eps = tol == tolerance.end() ? 0.0 : tol->second;
    SCOPED_TRACE("attribute " + x.name);
    const PointAttribute* y = b.find(x.name);
    ASSERT_NE(y, nullptr) << "missing after the round trip";
    EXPECT_EQ(x.components, y->components);
    if (same_type) {
      EXPECT_EQ(x.values.index(), y->values.index());
    }
    const size_t count = a.num_points() * static_cast<size_t>(x.components);
    size_t mismatches = 0;
    for (size_t k = 0; k < count; ++k) {
      const double u = as_double(x, k), v = as_double(*y, k);
      if (!(std::fabs(u - v) <= eps || (std::isnan(u) && std::isnan(v)))) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0u);
  }
}

template <class T>
std::vector<T>& add(PointData& d, const std::string& name, int comps, int seed) {
  auto& v = d.add<T>(name, comps);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = static_cast<T>((static_cast<int64_t>(i) * 7919 + seed * 31) % 200 - (std::is_signed_v<T> ? 100 : 0));
  return v;
}

PointData generated(size_t n, double base, unsigned seed) {
  PointData d;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  d.positions.resize(3 * n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) d.positions[3 * i + c] = base * (c + 1) + u(rng);
  return d;
}

// ---------------------------------------------------------------------- PLY

TEST(IoWritePly, AllAttributeTypesRoundTrip) {
  PointData d = generated(40000, 6617080.0, 1);  // more than one write chunk
  add<uint8_t>(d, "colors", 3, 1);
  add<uint8_t>(d, "alpha", 1, 2);
  add<float>(d, "normals", 3, 3);
  add<float>(d, "intensity", 1, 4);
  add<uint8_t>(d, "classification", 1, 5);
  add<int8_t>(d, "i8", 1, 6);
  add<uint16_t>(d, "u16", 1, 7);
  add<int16_t>(d, "i16", 1, 8);
  add<uint32_t>(d, "u32", 1, 9);
  add<int32_t>(d, "i32", 1, 10);
  add<double>(d, "gps_time", 1, 11)[5] = 123456789.123456789;
  add<float>(d, "f32", 1, 12)[7] = 1.25e-30f;
  d.metadata["comments"] = std::string("first\nsecond line");
  const std::string path = scratch("all_types.ply");
  write_point_cloud(path, d);
  PointData r = read_point_cloud(path);
  ASSERT_EQ(r.num_points(), d.num_points());
  EXPECT_EQ(r.positions, d.positions);  // doubles, bit for bit
  expect_same_attributes(d, r, true);
  EXPECT_EQ(r.attributes.size(), d.attributes.size());
  EXPECT_EQ(std::get<std::string>(r.metadata.at("encoding")), "binary_little_endian");
  EXPECT_EQ(std::get<std::string>(r.metadata.at("comments")),
            "written by PointNPR\nfirst\nsecond line");
  // Writing what was read gives the same file.
  const std::string again = scratch("all_types_again.ply");
  write_point_cloud(again, r);
  PointData r2 = read_point_cloud(again);
  EXPECT_EQ(r2.positions, d.positions);
  expect_same_attributes(d, r2, true);
  EXPECT_EQ(std::filesystem::file_size(path), std::filesystem::file_size(again));
}

TEST(IoWritePly, MultiComponentAnd64BitAttributes) {
  PointData d = generated(10, 0.0, 2);
  auto& m = d.add<uint16_t>("rgbn", 4);
  for (size_t i = 0; i < m.size(); ++i) m[i] = static_cast<uint16_t>(i * 1000);
  auto& big = d.add<int64_t>("id", 1);
  for (size_t i = 0; i < big.size(); ++i) big[i] = (int64_t{1} << 40) + static_cast<int64_t>(i);
  auto& odd = d.add<float>("x", 1);  // a name the reader would take for a coordinate
  for (size_t i = 0; i < odd.size(); ++i) odd[i] = static_cast<float>(i);
  const std::string path = scratch("multi.ply");
  write_point_cloud(path, d);
  PointData r = read_point_cloud(path);
  EXPECT_EQ(r.positions, d.positions);
  for (int c = 0; c < 4; ++c) {
    const auto* v = r.get<uint16_t>("rgbn_" + std::to_string(c));
    ASSERT_NE(v, nullptr) << c;
    for (size_t i = 0; i < 10; ++i) EXPECT_EQ((*v)[i], m[i * 4 + c]);
  }
  const auto* id = r.get<double>("id");  // PLY has no 64-bit integers: exact doubles
  ASSERT_NE(id, nullptr);
  for (size_t i = 0; i < 10; ++i) EXPECT_EQ((*id)[i], static_cast<double>(big[i]));
  const auto* x = r.get<float>("attr_x");
  ASSERT_NE(x, nullptr);
  EXPECT_EQ(*x, odd);

  big[3] = (int64_t{1} << 60) + 1;  // not a double
  EXPECT_THROW(write_point_cloud(scratch("inexact.ply"), d), Error);
  EXPECT_FALSE(std::filesystem::exists(scratch("inexact.ply")));
}

TEST(IoWritePly, RealFilesRoundTrip) {
  for (const char* name : {"tinyply_elephant.ply", "bun_zipper_res2.ply", "mug_crop.pcd",
                           "malformed/ply_assimp_float-color.ply",
                           "malformed/pcd_pcl_bun0_normals_ascii.pcd"}) {
    SCOPED_TRACE(name);
    PointData d = read_point_cloud(data_path(name));
    const std::string path = scratch("real.ply");
    write_point_cloud(path, d);
    PointData r = read_point_cloud(path);
    EXPECT_EQ(r.positions, d.positions);
    expect_same_attributes(d, r, true);
  }
}

TEST(IoWritePly, EmptyCloud) {
  PointData d;
  d.add<float>("intensity");
  write_point_cloud(scratch("empty.ply"), d);
  PointData r = read_point_cloud(scratch("empty.ply"));
  EXPECT_EQ(r.num_points(), 0u);
  EXPECT_TRUE(r.has("intensity"));
}

// ---------------------------------------------------------------------- LAS

TEST(IoWriteLas, RealFilesRoundTripExactly) {
  int with_crs = 0, with_extra = 0;
  for (const char* name :
       {"warsaw_small.las", "laspy_nebraska_classified.las", "lidarhd_myria3d_subset.las",
        "lion_takanawa_subset.las", "mvk-thin.las", "sample_c.las",
        "malformed/las_pdal_test1_4.las", "malformed/las_pdal_permutations_1.0_0.las",
        "malformed/las_laspy_unregistered_extra_bytes.las", "malformed/las_pdal_prec3.las"}) {
    SCOPED_TRACE(name);
    PointData d = read_point_cloud(data_path(name));
    const std::string path = scratch("real.las");
    write_point_cloud(path, d);
    PointData r = read_point_cloud(path);
    // The source grid holds every point, so it is kept: positions are exact.
    EXPECT_EQ(r.positions, d.positions);
    EXPECT_EQ(r.metadata.at("scale"), d.metadata.at("scale"));
    EXPECT_EQ(r.metadata.at("offset"), d.metadata.at("offset"));
    EXPECT_EQ(std::get<std::string>(r.metadata.at("version")), "1.4");
    // Formats 0-5 store whole degrees, 6-10 steps of 0.006 degrees.
    expect_same_attributes(d, r, true, {{"scan_angle", 0.003 + 1e-5}});
    // Header bounds are those of the written coordinates.
    for (int c = 0; c < 3; ++c) {
      double lo = INFINITY, hi = -INFINITY;
      for (size_t i = 0; i < r.num_points(); ++i)
        lo = std::min(lo, r.positions[3 * i + c]), hi = std::max(hi, r.positions[3 * i + c]);
      if (r.num_points() == 0) lo = hi = 0;
      EXPECT_EQ(std::get<std::vector<double>>(r.metadata.at("bounds_min"))[c], lo);
      EXPECT_EQ(std::get<std::vector<double>>(r.metadata.at("bounds_max"))[c], hi);
    }
    for (const char* key : {"crs_wkt", "crs_epsg", "system_identifier", "file_source_id", "creation_year",
                            "creation_day", "colors_all_zero"}) {
      EXPECT_EQ(d.metadata.count(key), r.metadata.count(key)) << key;
      if (d.metadata.count(key)) {
        EXPECT_EQ(d.metadata.at(key), r.metadata.at(key)) << key;
      }
    }
    const int64_t pf = std::get<int64_t>(r.metadata.at("point_format"));
    EXPECT_EQ(pf, d.has("nir") ? 8 : d.has("colors") ? 7 : 6);
    with_crs += d.metadata.count("crs_wkt") > 0;
    for (const PointAttribute& a : d.attributes)
      with_extra += a.name != "intensity" && a.name != "return_number" &&
                    a.name != "number_of_returns" && a.name != "classification" &&
                    a.name != "user_data" && a.name != "scan_angle" &&
                    a.name != "point_source_id" && a.name != "gps_time" && a.name != "colors" &&
                    a.name != "nir";
  }
  EXPECT_GT(with_crs, 0);    // the set exercises the WKT VLR
  EXPECT_GT(with_extra, 0);  // and extra bytes
}

TEST(IoWriteLas, GeneratedCloudQuantisedToATenthOfAMillimetre) {
  PointData d = generated(70000, 500000.0, 3);  // several write chunks
  add<float>(d, "normals", 3, 1);
  add<uint8_t>(d, "alpha", 1, 2);
  add<double>(d, "curvature", 1, 3)[9] = 0.123456789012345;
  add<int64_t>(d, "segment", 1, 4)[1] = int64_t{1} << 50;
  add<uint16_t>(d, "five", 5, 5);  // more than 3 components: split
  add<uint8_t>(d, "colors", 3, 6);
  add<uint16_t>(d, "intensity", 1, 7);  // another type than the reader's: values kept
  add<uint8_t>(d, "classification", 1, 8);
  auto& rn = d.add<uint8_t>("return_number");
  auto& nr = d.add<uint8_t>("number_of_returns");
  for (size_t i = 0; i < rn.size(); ++i) rn[i] = static_cast<uint8_t>(1 + i % 15), nr[i] = 15;
  auto& angle = d.add<float>("scan_angle");
  for (size_t i = 0; i < angle.size(); ++i)
    angle[i] = static_cast<float>((static_cast<int>(i % 60001) - 30000) * 0.006);
  const std::string wkt = "PROJCS[\"ETRS89 / Poland CS92\",AUTHORITY[\"EPSG\",\"2180\"]]";
  d.metadata["crs_wkt"] = wkt;
  d.metadata["crs_epsg"] = int64_t{2180};
  const std::string path = scratch("generated.las");
  write_point_cloud(path, d);
  PointData r = read_point_cloud(path);
  ASSERT_EQ(r.num_points(), d.num_points());
  const auto& scale = std::get<std::vector<double>>(r.metadata.at("scale"));
  double worst = 0;
  for (int c = 0; c < 3; ++c) EXPECT_LE(scale[c], 1e-4);
  for (size_t i = 0; i < d.positions.size(); ++i) {
    const double err = std::fabs(r.positions[i] - d.positions[i]);
    worst = std::max(worst, err);
    ASSERT_LE(err, scale[i % 3] * 0.5 + 1e-9) << i;
  }
  EXPECT_LE(worst, 0.5e-4);
  EXPECT_EQ(std::get<int64_t>(r.metadata.at("point_format")), 7);
  EXPECT_EQ(std::get<std::string>(r.metadata.at("crs_wkt")), wkt);
  EXPECT_EQ(std::get<int64_t>(r.metadata.at("crs_epsg")), 2180);
  // Standard fields come back in the reader's types, with the same values.
  PointData expected = d;
  expected.remove("five");
  expect_same_attributes(expected, r, false);
  EXPECT_NE(r.get<float>("intensity"), nullptr);
  // Extra bytes keep their type; 5 components became 3 + 2.
  EXPECT_NE(r.get<double>("curvature"), nullptr);
  EXPECT_NE(r.get<int64_t>("segment"), nullptr);
  EXPECT_NE(r.get<float>("normals"), nullptr);
  const auto* f0 = r.get<uint16_t>("five_0");
  const auto* f1 = r.get<uint16_t>("five_1");
  ASSERT_NE(f0, nullptr);
  ASSERT_NE(f1, nullptr);
  const auto& five = *d.get<uint16_t>("five");
  for (size_t i = 0; i < d.num_points(); ++i)
    for (int c = 0; c < 5; ++c)
      ASSERT_EQ(c < 3 ? (*f0)[i * 3 + c] : (*f1)[i * 2 + c - 3], five[i * 5 + c]);
}

TEST(IoWriteLas, ChoosesFormatAndNiceGrid) {
  PointData d;
  d.positions = {1.25, 2.5, 3.75, -100.01, 200.02, 0.0};  // on the 0.01 grid
  auto& nir = d.add<uint16_t>("nir");
  nir = {7, 65535};
  write_point_cloud(scratch("nir.las"), d);
  PointData r = read_point_cloud(scratch("nir.las"));
  EXPECT_EQ(r.positions, d.positions);
  EXPECT_EQ(std::get<int64_t>(r.metadata.at("point_format")), 8);
  EXPECT_EQ(std::get<std::vector<double>>(r.metadata.at("scale")),
            (std::vector<double>{0.01, 0.01, 0.01}));
  EXPECT_EQ(*r.get<uint16_t>("nir"), nir);
  EXPECT_TRUE(r.metadata.count("colors_all_zero"));  // format 8 without colours

  PointData e;
  e.positions = {0.1, 0.2, 0.3};
  write_point_cloud(scratch("plain.las"), e);
  PointData re = read_point_cloud(scratch("plain.las"));
  EXPECT_EQ(std::get<int64_t>(re.metadata.at("point_format")), 6);
  EXPECT_NEAR(re.positions[0], 0.1, 1e-12);

  PointData empty;
  write_point_cloud(scratch("empty.las"), empty);
  EXPECT_EQ(read_point_cloud(scratch("empty.las")).num_points(), 0u);
}

TEST(IoWriteLas, RefusesWhatLasCannotHold) {
  PointData d;
  d.positions = {0, 0, 0, 1, 1, 1};
  auto& cls = d.add<int32_t>("classification");
  cls = {3, 300};
  try {
    write_point_cloud(scratch("bad.las"), d);
    ADD_FAILURE() << "expected Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'classification' has the value 300 at point 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(scratch("bad.las")));  // no partial file

  PointData nan;
  nan.positions = {0, 0, NAN};
  EXPECT_THROW(write_point_cloud(scratch("nan.las"), nan), Error);
  EXPECT_THROW(write_point_cloud(scratch("nan.ply"), nan), Error);
  EXPECT_THROW(write_point_cloud(scratch("cloud.xyz"), d), Error);
  EXPECT_THROW(write_point_cloud(scratch("no_such_dir/cloud.las"), d), Error);
  PointData bad;
  bad.positions = {0, 0, 0};
  bad.attributes.push_back(PointAttribute{"short", 1, std::vector<float>{}});
  EXPECT_THROW(write_point_cloud(scratch("short.ply"), bad), Error);
}

// ------------------------------------------------------------------- memory

TEST(IoReadMemory, SameResultAsTheFile) {
  for (const char* name : {"warsaw_small.las", "tinyply_elephant.ply", "mug_crop.pcd",
                           "malformed/text_pdal_crlf_test.txt"}) {
    SCOPED_TRACE(name);
    const std::string path = data_path(name);
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto* p = reinterpret_cast<const uint8_t*>(bytes.data());
    const std::string ext = path.substr(path.rfind('.'));
    PointData m = ext == ".las"   ? read_las_memory(p, bytes.size(), path)
                  : ext == ".ply" ? read_ply_memory(p, bytes.size(), path)
                  : ext == ".pcd" ? read_pcd_memory(p, bytes.size(), path)
                                  : read_text_memory(p, bytes.size(), path);
    PointData f = read_point_cloud(path);
    EXPECT_EQ(m.positions, f.positions);
    expect_same_attributes(f, m, true);
  }
  try {
    const uint8_t junk[] = {'L', 'A', 'S', 'F', 0};
    read_las_memory(junk, sizeof junk, "<fuzz>");
    ADD_FAILURE() << "expected ReadError";
  } catch (const ReadError& e) {
    EXPECT_EQ(e.file(), "<fuzz>");
  }
}

}  // namespace
}  // namespace pointnpr
