// PCL PCD reader (v0.5-0.7 headers; ascii, binary, binary_compressed/LZF).
//
// Organized clouds (HEIGHT > 1) mark missing points with NaN; those points
// are dropped. Counts are checked against the file size (and, for LZF, the
// largest possible expansion of the compressed bytes) before allocating.
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {
namespace {

using io::load_le;
using io::narrow_float;

struct Field {
  std::string name;
  size_t size = 4;
  char type = 'F';  // I, U, F
  size_t count = 1;
  size_t offset = 0;  // within a point record (binary / ascii column index for ascii)
};

enum class Role { Skip, Position, Normal, Color, Intensity, Other };

std::vector<std::string_view> split_ws(std::string_view line) {
  std::vector<std::string_view> tok;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) tok.push_back(line.substr(i, j - i));
    i = j;
  }
  return tok;
}

bool parse_u64(std::string_view s, uint64_t& v) {
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parse_finite(std::string_view s, double& v) {
  auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(v);
}

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

class PcdReader : private io::ReaderBase {
 public:
  using ReaderBase::ReaderBase;
  PointData read();

 private:
  void parse_header();
  void plan(PointData& out);
  // Stores element `c` of field `fi` of point `i`; `bits` is the raw 32-bit
  // pattern for colour fields.
  void store(size_t fi, size_t c, size_t i, double v, uint32_t bits);
  // Decodes field fi of all points: element c of point i lies at
  // src + i * stride + c * size (binary: record-major; compressed: field-major).
  void decode_field(size_t fi, const uint8_t* src, size_t stride, uint64_t n);
  template <class T>
  void decode_field_typed(size_t fi, const uint8_t* src, size_t stride, uint64_t n);
  void lzf_decompress(const uint8_t* in, size_t in_len, uint8_t* out, size_t out_len, size_t at);


  std::vector<Field> fields_;
  uint64_t width_ = 0, height_ = 1, points_ = 0;
  std::array<double, 3> viewpoint_{0.0, 0.0, 0.0};  // VIEWPOINT's translation
  bool have_points_ = false;
  std::string data_kind_;
  size_t data_start_ = 0;
  std::string version_;
  size_t record_size_ = 0;

  std::vector<Role> role_;
  std::vector<int> comp_;
  double* positions_ = nullptr;
  float* normals_ = nullptr;
  uint8_t* colors_ = nullptr;
  float* intensity_ = nullptr;
  std::vector<float*> other_;
};

void PcdReader::parse_header() {
  if (size_ == 0) fail("file is empty (0 bytes)");
  size_t pos = 0;
  bool have_fields = false, have_size = false, have_type = false, have_width = false;
  std::vector<std::string_view> sizes, types, counts;
  while (pos < size_) {
    const size_t start = pos;
    const uint8_t* nl = static_cast<const uint8_t*>(std::memchr(d_ + pos, '\n', size_ - pos));
    const size_t end = nl ? static_cast<size_t>(nl - d_) : size_;
    pos = nl ? end + 1 : size_;
    std::string_view line(reinterpret_cast<const char*>(d_ + start), end - start);
    auto tok = split_ws(line);
    if (tok.empty() || tok[0][0] == '#') continue;
    const std::string key = lower(tok[0]);
    const auto at = static_cast<int64_t>(start);
    if (key == "version") {
      if (tok.size() > 1) version_ = std::string(tok[1]);
    } else if (key == "fields" || key == "columns") {
      for (size_t i = 1; i < tok.size(); ++i) fields_.push_back(Field{std::string(tok[i])});
      have_fields = true;
    } else if (key == "size") {
      sizes.assign(tok.begin() + 1, tok.end());
      have_size = true;
    } else if (key == "type") {
      types.assign(tok.begin() + 1, tok.end());
      have_type = true;
    } else if (key == "count") {
      counts.assign(tok.begin() + 1, tok.end());
    } else if (key == "width") {
      if (tok.size() != 2 || !parse_u64(tok[1], width_)) fail("invalid WIDTH line", at);
      have_width = true;
    } else if (key == "height") {
      if (tok.size() != 2 || !parse_u64(tok[1], height_)) fail("invalid HEIGHT line", at);
    } else if (key == "points") {
      if (tok.size() != 2 || !parse_u64(tok[1], points_)) fail("invalid POINTS line", at);
      have_points_ = true;
    } else if (key == "viewpoint") {
      // Sensor pose; the points are already in the cloud's frame, so only
      // its position is kept (an organized frame's normals face it). One
      // that does not parse is the default, the origin, as before.
      std::array<double, 3> t{};
      if (tok.size() == 8 && parse_finite(tok[1], t[0]) && parse_finite(tok[2], t[1]) && parse_finite(tok[3], t[2]))
        viewpoint_ = t;
    } else if (key == "data") {
      if (tok.size() != 2) fail("invalid DATA line", at);
      data_kind_ = lower(tok[1]);
      data_start_ = pos;
      break;
    } else {
      fail("the PCD header is missing or incomplete: expected header lines (VERSION, FIELDS, "
           "SIZE, TYPE, COUNT, WIDTH, HEIGHT, POINTS, DATA) but found '" +
               std::string(line.substr(0, 60)) + "'",
           at);
    }
  }
  if (data_kind_.empty()) fail("the PCD header has no DATA line; the file is truncated or not a PCD file");
  if (!have_fields || fields_.empty()) fail("the PCD header has no FIELDS line");
  if (!have_size || !have_type) fail("the PCD header lacks a SIZE or TYPE line");
  if (sizes.size() != fields_.size() || types.size() != fields_.size() ||
      (!counts.empty() && counts.size() != fields_.size()))
    fail("the PCD header's FIELDS, SIZE, TYPE and COUNT lines list different numbers of entries (" +
         std::to_string(fields_.size()) + " fields, " + std::to_string(sizes.size()) + " sizes, " +
         std::to_string(types.size()) + " types, " + std::to_string(counts.size()) + " counts)");
  if (!have_width && !have_points_) fail("the PCD header has neither WIDTH nor POINTS");
  if (!have_points_) points_ = width_ * height_;
  if (have_width && width_ * height_ != points_)
    fail("the PCD header is inconsistent: WIDTH " + std::to_string(width_) + " x HEIGHT " +
         std::to_string(height_) + " != POINTS " + std::to_string(points_));
  size_t off = 0;
  for (size_t i = 0; i < fields_.size(); ++i) {
    Field& f = fields_[i];
    uint64_t s = 0, c = 1;
    if (!parse_u64(sizes[i], s) || (s != 1 && s != 2 && s != 4 && s != 8))
      fail("field '" + f.name + "' has invalid SIZE '" + std::string(sizes[i]) + "'");
    if (types[i].size() != 1 || (types[i][0] != 'F' && types[i][0] != 'I' && types[i][0] != 'U'))
      fail("field '" + f.name + "' has invalid TYPE '" + std::string(types[i]) + "'");
    if (!counts.empty() && (!parse_u64(counts[i], c) || c == 0 || c > 100000))
      fail("field '" + f.name + "' has invalid COUNT '" + std::string(counts[i]) + "'");
    f.size = s;
    f.type = types[i][0];
    f.count = c;
    if (f.type == 'F' && s != 4 && s != 8)
      fail("field '" + f.name + "' is a float of size " + std::to_string(s));
    f.offset = off;
    off += f.size * f.count;
  }
  record_size_ = off;
}

void PcdReader::plan(PointData& out) {
  const size_t nf = fields_.size();
  role_.assign(nf, Role::Other);
  comp_.assign(nf, 0);
  auto find = [&](std::initializer_list<const char*> names) -> int {
    for (const char* n : names)
      for (size_t i = 0; i < nf; ++i)
        if (fields_[i].count == 1 && lower(fields_[i].name) == n) return static_cast<int>(i);
    return -1;
  };
  const int xyz[3] = {find({"x"}), find({"y"}), find({"z"})};
  for (int c = 0; c < 3; ++c) {
    if (xyz[c] < 0)
      fail(std::string("the PCD file has no '") + "xyz"[c] + "' field; a point cloud needs x, y and z");
    role_[xyz[c]] = Role::Position;
    comp_[xyz[c]] = c;
  }
  const int nrm[3] = {find({"normal_x", "nx"}), find({"normal_y", "ny"}), find({"normal_z", "nz"})};
  const bool normals = nrm[0] >= 0 && nrm[1] >= 0 && nrm[2] >= 0;
  if (normals)
    for (int c = 0; c < 3; ++c) {
      role_[nrm[c]] = Role::Normal;
      comp_[nrm[c]] = c;
    }
  const int rgb = find({"rgb", "rgba"});
  if (rgb >= 0 && fields_[rgb].size == 4) role_[rgb] = Role::Color;
  const int inten = find({"intensity"});
  if (inten >= 0) role_[inten] = Role::Intensity;

  const uint64_t n = points_;
  io::resize_fresh(out.positions, n * 3);
  positions_ = out.positions.data();
  if (normals) normals_ = out.add<float>("normals", 3).data();
  if (rgb >= 0 && role_[rgb] == Role::Color) colors_ = out.add<uint8_t>("colors", 3).data();
  if (inten >= 0) intensity_ = out.add<float>("intensity").data();
  other_.assign(nf, nullptr);
  for (size_t i = 0; i < nf; ++i) {
    if (role_[i] != Role::Other) continue;
    if (fields_[i].name == "_") {  // PCL padding
      role_[i] = Role::Skip;
      continue;
    }
    std::string name = fields_[i].name;
    while (out.has(name)) name = "pcd_" + name;
    other_[i] = out.add<float>(name, static_cast<int>(fields_[i].count)).data();
  }
}

void PcdReader::store(size_t fi, size_t c, size_t i, double v, uint32_t bits) {
  switch (role_[fi]) {
    case Role::Skip: break;
    case Role::Position: positions_[3 * i + comp_[fi]] = v; break;
    case Role::Normal: normals_[3 * i + comp_[fi]] = narrow_float(v); break;
    case Role::Color:
      colors_[3 * i + 0] = static_cast<uint8_t>(bits >> 16);
      colors_[3 * i + 1] = static_cast<uint8_t>(bits >> 8);
      colors_[3 * i + 2] = static_cast<uint8_t>(bits);
      break;
    case Role::Intensity: intensity_[i] = narrow_float(v); break;
    case Role::Other: other_[fi][i * fields_[fi].count + c] = narrow_float(v); break;
  }
}

template <class T>
void PcdReader::decode_field_typed(size_t fi, const uint8_t* src, size_t stride, uint64_t n) {
  const Field& f = fields_[fi];
  auto value = [&](uint64_t i, size_t c) {
    return load_le<T>(src + i * stride + c * sizeof(T));
  };
  auto to_float = [](T v) {
    if constexpr (std::is_same_v<T, float>)
      return v;
    else
      return narrow_float(static_cast<double>(v));
  };
  switch (role_[fi]) {
    case Role::Skip: break;
    case Role::Position: {
      const size_t k = static_cast<size_t>(comp_[fi]);
      for (uint64_t i = 0; i < n; ++i) positions_[3 * i + k] = static_cast<double>(value(i, 0));
      break;
    }
    case Role::Normal: {
      const size_t k = static_cast<size_t>(comp_[fi]);
      for (uint64_t i = 0; i < n; ++i) normals_[3 * i + k] = to_float(value(i, 0));
      break;
    }
    case Role::Color:  // packed 0x00RRGGBB / 0xAARRGGBB in a 4-byte field
      for (uint64_t i = 0; i < n; ++i) {
        const uint32_t bits = load_le<uint32_t>(src + i * stride);
        colors_[3 * i + 0] = static_cast<uint8_t>(bits >> 16);
        colors_[3 * i + 1] = static_cast<uint8_t>(bits >> 8);
        colors_[3 * i + 2] = static_cast<uint8_t>(bits);
      }
      break;
    case Role::Intensity:
      for (uint64_t i = 0; i < n; ++i) intensity_[i] = to_float(value(i, 0));
      break;
    case Role::Other: {
      float* dst = other_[fi];
      const size_t count = f.count;
      for (uint64_t i = 0; i < n; ++i)
        for (size_t c = 0; c < count; ++c) dst[i * count + c] = to_float(value(i, c));
      break;
    }
  }
}

void PcdReader::decode_field(size_t fi, const uint8_t* src, size_t stride, uint64_t n) {
  const Field& f = fields_[fi];
  if (f.type == 'F') {
    if (f.size == 8) return decode_field_typed<double>(fi, src, stride, n);
    return decode_field_typed<float>(fi, src, stride, n);
  }
  const bool u = f.type == 'U';
  switch (f.size) {
    case 1: return u ? decode_field_typed<uint8_t>(fi, src, stride, n)
                     : decode_field_typed<int8_t>(fi, src, stride, n);
    case 2: return u ? decode_field_typed<uint16_t>(fi, src, stride, n)
                     : decode_field_typed<int16_t>(fi, src, stride, n);
    case 4: return u ? decode_field_typed<uint32_t>(fi, src, stride, n)
                     : decode_field_typed<int32_t>(fi, src, stride, n);
    default: return u ? decode_field_typed<uint64_t>(fi, src, stride, n)
                      : decode_field_typed<int64_t>(fi, src, stride, n);
  }
}

void PcdReader::lzf_decompress(const uint8_t* in, size_t in_len, uint8_t* out, size_t out_len,
                               size_t at) {
  size_t ip = 0, op = 0;
  auto corrupt = [&](const char* what) {
    fail(std::string("corrupt LZF data in binary_compressed PCD: ") + what,
         static_cast<int64_t>(at + ip));
  };
  while (ip < in_len) {
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {
      const size_t len = ctrl + 1;
      if (ip + len > in_len) corrupt("literal run past the end of the input");
      if (op + len > out_len) corrupt("output larger than declared");
      std::memcpy(out + op, in + ip, len);
      ip += len;
      op += len;
    } else {
      size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in_len) corrupt("truncated back-reference");
        len += in[ip++];
      }
      if (ip >= in_len) corrupt("truncated back-reference");
      const size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
      len += 2;
      if (back > op) corrupt("back-reference before the start of the output");
      if (op + len > out_len) corrupt("output larger than declared");
      if (back >= len) {  // no overlap
        std::memcpy(out + op, out + op - back, len);
        op += len;
      } else {
        for (size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
      }
    }
  }
  if (op != out_len)
    fail("corrupt LZF data in binary_compressed PCD: decompressed to " + std::to_string(op) +
             " bytes, the header declares " + std::to_string(out_len),
         static_cast<int64_t>(at));
}

PointData PcdReader::read() {
  parse_header();
  const uint64_t n = points_;
  const size_t remaining = size_ - data_start_;
  const auto at = static_cast<int64_t>(data_start_);
  // Bound the point count by the file size before allocating anything.
  if (data_kind_ == "binary") {
    if (record_size_ > 0 && n > remaining / record_size_)
      fail("file is truncated: the header declares " + std::to_string(n) + " points of " +
               std::to_string(record_size_) + " bytes, but only " + std::to_string(remaining) +
               " bytes of data follow",
           at);
  } else if (data_kind_ == "ascii") {
    size_t values = 0;
    for (const Field& f : fields_) values += f.count;
    if (n > (remaining + 1) / (2 * values))
      fail("file is truncated: the header declares " + std::to_string(n) + " points of " +
               std::to_string(values) + " values, more than the remaining " +
               std::to_string(remaining) + " bytes can hold",
           at);
  } else if (data_kind_ == "binary_compressed") {
    if (remaining < 8) fail("file is truncated: binary_compressed data has no size words", at);
    const uint32_t csize = load_le<uint32_t>(d_ + data_start_);
    const uint32_t usize = load_le<uint32_t>(d_ + data_start_ + 4);
    if (csize > remaining - 8)
      fail("file is truncated: " + std::to_string(csize) + " compressed bytes declared, " +
               std::to_string(remaining - 8) + " present",
           at);
    if (record_size_ > 0 && n > std::numeric_limits<uint64_t>::max() / record_size_)
      fail("POINTS " + std::to_string(n) + " is impossibly large", at);
    if (usize != n * record_size_)
      fail("binary_compressed data decompresses to " + std::to_string(usize) +
               " bytes, but POINTS x record size is " + std::to_string(n * record_size_),
           at + 4);
    // LZF expands at most 264 output bytes per 3 input bytes.
    if (usize > static_cast<uint64_t>(csize) * 88 + 264)
      fail("binary_compressed data declares " + std::to_string(usize) +
               " bytes, more than " + std::to_string(csize) + " LZF bytes can hold",
           at + 4);
  } else {
    fail("unknown PCD DATA kind '" + data_kind_ + "' (expected ascii, binary or binary_compressed)");
  }

  PointData out;
  plan(out);
  const size_t nf = fields_.size();

  if (data_kind_ == "binary") {
    const uint8_t* base = d_ + data_start_;
    for (size_t fi = 0; fi < nf; ++fi)
      decode_field(fi, base + fields_[fi].offset, record_size_, n);
  } else if (data_kind_ == "binary_compressed") {
    const uint32_t csize = load_le<uint32_t>(d_ + data_start_);
    std::vector<uint8_t> raw;
    io::resize_fresh(raw, n * record_size_);
    lzf_decompress(d_ + data_start_ + 8, csize, raw.data(), raw.size(), data_start_ + 8);
    // Field-major layout: all values of field 0, then of field 1, ...
    size_t field_start = 0;
    for (size_t fi = 0; fi < nf; ++fi) {
      const size_t stride = fields_[fi].size * fields_[fi].count;
      decode_field(fi, raw.data() + field_start, stride, n);
      field_start += stride * n;
    }
  } else {  // ascii
    size_t pos = data_start_;
    for (uint64_t i = 0; i < n; ++i) {
      for (size_t fi = 0; fi < nf; ++fi) {
        const Field& f = fields_[fi];
        for (size_t c = 0; c < f.count; ++c) {
          while (pos < size_ && (d_[pos] == ' ' || d_[pos] == '\t' || d_[pos] == '\r' || d_[pos] == '\n')) ++pos;
          if (pos >= size_)
            fail("file is truncated: the data ends after " + std::to_string(i) + " of " +
                     std::to_string(n) + " points",
                 static_cast<int64_t>(size_));
          const size_t start = pos;
          while (pos < size_ && d_[pos] != ' ' && d_[pos] != '\t' && d_[pos] != '\r' && d_[pos] != '\n') ++pos;
          const char* b = reinterpret_cast<const char*>(d_ + start);
          const char* e = reinterpret_cast<const char*>(d_ + pos);
          double v = 0;
          uint32_t bits = 0;
          bool ok;
          if (role_[fi] == Role::Color) {
            // PCL packs colour into the bits of a 32-bit field. In ascii it
            // writes the packed value as an unsigned integer (older versions
            // as a float-formatted integer such as 4.2108e+06); a value that
            // is not an integer is taken as the float whose bits hold it.
            double dv = 0;
            auto r = std::from_chars(b, e, dv);
            ok = r.ec == std::errc() && r.ptr == e;
            if (ok && dv >= 0 && dv <= 4294967295.0 && dv == std::floor(dv))
              bits = static_cast<uint32_t>(dv);
            else if (ok)
              bits = std::bit_cast<uint32_t>(narrow_float(dv));
          } else {
            if (b < e && *b == '+') ++b;
            auto r = std::from_chars(b, e, v);
            ok = r.ec == std::errc() && r.ptr == e;
          }
          if (!ok)
            fail("invalid value '" + std::string(reinterpret_cast<const char*>(d_ + start), std::min<size_t>(pos - start, 40)) +
                     "' for field '" + f.name + "' of point " + std::to_string(i),
                 static_cast<int64_t>(start));
          store(fi, c, i, v, bits);
        }
      }
    }
  }

  auto& md = out.metadata;
  md["format"] = std::string("pcd");
  md["version"] = version_;
  md["encoding"] = data_kind_;
  md["width"] = static_cast<int64_t>(width_);
  md["height"] = static_cast<int64_t>(height_);
  md["point_count"] = static_cast<int64_t>(n);
  md["organized"] = static_cast<int64_t>(height_ > 1 ? 1 : 0);
  // An organized cloud is one sensor's frame: where that sensor stood.
  if (height_ > 1) md["sensor_origin"] = std::vector<double>(viewpoint_.begin(), viewpoint_.end());
  out.drop_nonfinite_points();
  return out;
}

}  // namespace

PointData read_pcd(const std::string& path) {
  PcdReader reader(path);
  return reader.read();
}

PointData read_pcd_memory(const uint8_t* data, size_t size, const std::string& name) {
  PcdReader reader(name, data, size);
  return reader.read();
}

}  // namespace pointnpr
