#pragma once
// Helpers shared by the reader tests: paths to the copied test files, a
// scratch directory, and byte builders for generated LAS/PLY files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/error.h"
#include "io/readers.h"

namespace pointnpr::test_io {

inline std::string data_path(const std::string& rel) {
  return std::string(POINTNPR_TEST_DATA_DIR) + "/io/" + rel;
}

// Generated files go to a per-process folder, removed when the tests end.
inline std::filesystem::path scratch_path() {
  return std::filesystem::temp_directory_path() /
         ("pointnpr_io_tests_" + std::to_string(::getpid()));
}

inline std::filesystem::path scratch_dir() {
  static const std::filesystem::path dir = [] {
    auto d = scratch_path();
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

class ScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(scratch_path(), ec);
  }
};
inline ::testing::Environment* const kScratchCleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

inline std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = (scratch_dir() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

// The ReadError thrown by reading `path`; fails the test if none is thrown.
inline std::string read_error_message(const std::string& path) {
  try {
    read_point_cloud(path);
  } catch (const ReadError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ReadError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected ReadError reading " << path;
  return "";
}

#define EXPECT_READ_ERROR(path, needle)                                              \
  do {                                                                               \
    const std::string msg_ = ::pointnpr::test_io::read_error_message(path);          \
    EXPECT_NE(msg_.find(needle), std::string::npos) << "message: " << msg_;          \
  } while (0)

// Little-endian byte string builder.
struct Bytes {
  std::string s;
  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
  template <class T>
  Bytes& put_be(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (size_t i = sizeof(T); i-- > 0;) s.push_back(b[i]);
    return *this;
  }
  Bytes& text(const std::string& t, size_t width) {  // fixed-width, NUL padded
    std::string f = t.substr(0, width);
    f.resize(width, '\0');
    s += f;
    return *this;
  }
  Bytes& raw(const std::string& t) {
    s += t;
    return *this;
  }
  Bytes& zeros(size_t n) {
    s.append(n, '\0');
    return *this;
  }
  size_t size() const { return s.size(); }
};

template <class T>
void poke(std::string& s, size_t offset, T v) {
  std::memcpy(&s[offset], &v, sizeof(T));
}

// A generated LAS point; fields absent from the format are ignored.
struct LasPoint {
  int32_t x = 0, y = 0, z = 0;
  uint16_t intensity = 0;
  uint8_t return_number = 1, number_of_returns = 1;
  uint8_t classification = 0;  // written raw (legacy formats keep flags in bits 5-7)
  double scan_angle = 0;       // degrees
  uint8_t user_data = 0;
  uint16_t point_source_id = 0;
  double gps_time = 0;
  uint16_t rgb[3] = {0, 0, 0};
  uint16_t nir = 0;
  std::string extra;  // appended after the standard fields
};

struct LasVlr {
  std::string user_id;
  uint16_t record_id = 0;
  std::string payload;
};

struct LasSpec {
  int version_minor = 2;
  int point_format = 3;
  int record_length = 0;  // 0 = standard length + extra size of the first point
  double scale[3] = {0.01, 0.01, 0.01};
  double offset[3] = {0, 0, 0};
  std::vector<LasVlr> vlrs;
  std::vector<LasVlr> evlrs;  // 1.4 only
  std::vector<LasPoint> points;
};

inline std::string las_point_bytes(const LasSpec& spec, const LasPoint& p) {
  static const int gps_at[11] = {-1, 20, -1, 20, 20, 20, 22, 22, 22, 22, 22};
  static const int rgb_at[11] = {-1, -1, 20, 28, -1, 28, -1, 30, 30, -1, 30};
  static const int nir_at[11] = {-1, -1, -1, -1, -1, -1, -1, -1, 36, -1, 36};
  static const int base_len[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  const int pf = spec.point_format;
  std::string r(static_cast<size_t>(base_len[pf]), '\0');
  poke(r, 0, p.x);
  poke(r, 4, p.y);
  poke(r, 8, p.z);
  poke(r, 12, p.intensity);
  if (pf >= 6) {
    r[14] = static_cast<char>((p.return_number & 15) | (p.number_of_returns << 4));
    r[16] = static_cast<char>(p.classification);
    r[17] = static_cast<char>(p.user_data);
    poke(r, 18, static_cast<int16_t>(std::lround(p.scan_angle / 0.006)));
    poke(r, 20, p.point_source_id);
  } else {
    r[14] = static_cast<char>((p.return_number & 7) | ((p.number_of_returns & 7) << 3));
    r[15] = static_cast<char>(p.classification);
    r[16] = static_cast<char>(static_cast<int8_t>(p.scan_angle));
    r[17] = static_cast<char>(p.user_data);
    poke(r, 18, p.point_source_id);
  }
  if (gps_at[pf] >= 0) poke(r, static_cast<size_t>(gps_at[pf]), p.gps_time);
  if (rgb_at[pf] >= 0)
    for (int c = 0; c < 3; ++c) poke(r, static_cast<size_t>(rgb_at[pf] + 2 * c), p.rgb[c]);
  if (nir_at[pf] >= 0) poke(r, static_cast<size_t>(nir_at[pf]), p.nir);
  return r + p.extra;
}

inline std::string make_las(const LasSpec& spec) {
  static const int base_len[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  const int minor = spec.version_minor;
  const uint16_t header_size = minor >= 4 ? 375 : minor == 3 ? 235 : 227;
  int rl = spec.record_length;
  if (rl == 0)
    rl = base_len[spec.point_format] +
         static_cast<int>(spec.points.empty() ? 0 : spec.points[0].extra.size());
  Bytes vl;
  for (const LasVlr& v : spec.vlrs) {
    vl.put<uint16_t>(0).text(v.user_id, 16).put<uint16_t>(v.record_id);
    vl.put<uint16_t>(static_cast<uint16_t>(v.payload.size())).text("", 32).raw(v.payload);
  }
  const uint32_t point_offset = header_size + static_cast<uint32_t>(vl.size());
  std::string pts;
  for (const LasPoint& p : spec.points) pts += las_point_bytes(spec, p);
  const uint64_t n = spec.points.size();
  Bytes h;
  h.raw("LASF").put<uint16_t>(0).put<uint16_t>(minor >= 4 ? 16 : 0).zeros(16);
  h.put<uint8_t>(1).put<uint8_t>(static_cast<uint8_t>(minor));
  h.text("pointnpr tests", 32).text("test_io_util.h", 32).put<uint16_t>(1).put<uint16_t>(2026);
  h.put<uint16_t>(header_size).put<uint32_t>(point_offset);
  h.put<uint32_t>(static_cast<uint32_t>(spec.vlrs.size()));
  h.put<uint8_t>(static_cast<uint8_t>(spec.point_format)).put<uint16_t>(static_cast<uint16_t>(rl));
  const bool legacy_zero = minor >= 4 && spec.point_format >= 6;
  h.put<uint32_t>(legacy_zero ? 0 : static_cast<uint32_t>(n));
  for (int i = 0; i < 5; ++i) h.put<uint32_t>(0);
  for (double s : spec.scale) h.put<double>(s);
  for (double o : spec.offset) h.put<double>(o);
  for (int i = 0; i < 6; ++i) h.put<double>(0);  // bounds (unchecked)
  if (minor >= 3) h.put<uint64_t>(0);            // waveform data start
  const uint64_t evlr_start = point_offset + pts.size();
  if (minor >= 4) {
    h.put<uint64_t>(spec.evlrs.empty() ? 0 : evlr_start);
    h.put<uint32_t>(static_cast<uint32_t>(spec.evlrs.size()));
    h.put<uint64_t>(n);
    for (int i = 0; i < 15; ++i) h.put<uint64_t>(0);
  }
  EXPECT_EQ(h.size(), header_size);
  Bytes ev;
  for (const LasVlr& v : spec.evlrs) {
    ev.put<uint16_t>(0).text(v.user_id, 16).put<uint16_t>(v.record_id);
    ev.put<uint64_t>(v.payload.size()).text("", 32).raw(v.payload);
  }
  return h.s + vl.s + pts + ev.s;
}

// One 192-byte extra bytes descriptor (LAS 1.4 R15 table 24).
inline std::string extra_bytes_descriptor(const std::string& name, uint8_t type, bool scaled,
                                          double scale = 1, double offset = 0) {
  Bytes b;
  b.put<uint16_t>(0).put<uint8_t>(type).put<uint8_t>(scaled ? (8 | 16) : 0).text(name, 32);
  b.zeros(4).zeros(24).zeros(24).zeros(24);  // unused, no_data, min, max
  for (int c = 0; c < 3; ++c) b.put<double>(c == 0 ? scale : 0);
  for (int c = 0; c < 3; ++c) b.put<double>(c == 0 ? offset : 0);
  b.text(name + " description", 32);
  EXPECT_EQ(b.size(), 192u);
  return b.s;
}

// A typed attribute of `d`; throws (failing the test) when absent or of another type.
template <class T>
const std::vector<T>& attr(const PointData& d, const std::string& name) {
  const std::vector<T>* v = d.get<T>(name);
  if (!v) throw std::runtime_error("missing attribute or wrong type: " + name);
  return *v;
}

}  // namespace pointnpr::test_io
