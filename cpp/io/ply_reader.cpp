// Stanford PLY reader (ascii, binary_little_endian, binary_big_endian).
//
// Only the vertex element is decoded; every other element (faces, tristrips,
// range grids, ...) is walked so that its size is checked and the vertex
// element is found wherever it lies. Element counts are checked against the
// bytes left in the file before anything is allocated.
#include <algorithm>
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
#include "io/gaussians.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {
namespace {

using io::narrow_float;

static_assert(std::endian::native == std::endian::little, "PLY reader assumes a little-endian host");

enum class PType { I8, U8, I16, U16, I32, U32, F32, F64 };

bool parse_type(std::string_view s, PType& t) {
  struct Entry {
    const char* name;
    PType type;
  };
  static const Entry table[] = {
      {"char", PType::I8},     {"int8", PType::I8},     {"uchar", PType::U8},
      {"uint8", PType::U8},    {"short", PType::I16},   {"int16", PType::I16},
      {"ushort", PType::U16},  {"uint16", PType::U16},  {"int", PType::I32},
      {"int32", PType::I32},   {"uint", PType::U32},    {"uint32", PType::U32},
      {"float", PType::F32},   {"float32", PType::F32}, {"double", PType::F64},
      {"float64", PType::F64},
  };
  for (const Entry& e : table)
    if (s == e.name) {
      t = e.type;
      return true;
    }
  return false;
}

size_t type_size(PType t) {
  switch (t) {
    case PType::I8: case PType::U8: return 1;
    case PType::I16: case PType::U16: return 2;
    case PType::I32: case PType::U32: case PType::F32: return 4;
    case PType::F64: return 8;
  }
  return 0;
}

bool is_integer_type(PType t) { return t != PType::F32 && t != PType::F64; }

// Whether an ascii value is an integer within the range of integer type t.
bool fits_integer(PType t, double v) {
  if (v != std::floor(v)) return false;  // also false for NaN
  switch (t) {
    case PType::I8: return v >= -128 && v <= 127;
    case PType::U8: return v >= 0 && v <= 255;
    case PType::I16: return v >= -32768 && v <= 32767;
    case PType::U16: return v >= 0 && v <= 65535;
    case PType::I32: return v >= -2147483648.0 && v <= 2147483647.0;
    case PType::U32: return v >= 0 && v <= 4294967295.0;
    default: return true;
  }
}

struct Property {
  std::string name;
  bool is_list = false;
  PType type = PType::F32;
  PType count_type = PType::U8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
  bool has_list() const {
    for (const Property& p : props)
      if (p.is_list) return true;
    return false;
  }
  // Record size when there are no lists; minimum size otherwise.
  size_t min_record_size() const {
    size_t s = 0;
    for (const Property& p : props) s += p.is_list ? type_size(p.count_type) : type_size(p.type);
    return s;
  }
};

enum class Encoding { Ascii, BinaryLE, BinaryBE };

// Where one decoded vertex property goes: a double (positions) or float
// column with a stride (components) and a component index.
struct Sink {
  double* d = nullptr;
  float* f = nullptr;
  size_t stride = 1;
  size_t comp = 0;
  void put(size_t i, double v) const {
    if (d)
      d[i * stride + comp] = v;
    else if (f)
      f[i * stride + comp] = narrow_float(v);
  }
};

template <class T, bool BE>
inline T load(const uint8_t* p) {
  if constexpr (BE)
    return io::load_be<T>(p);
  else
    return io::load_le<T>(p);
}

template <bool BE>
double load_as_double(PType t, const uint8_t* p) {
  switch (t) {
    case PType::I8: return static_cast<int8_t>(*p);
    case PType::U8: return *p;
    case PType::I16: return load<int16_t, BE>(p);
    case PType::U16: return load<uint16_t, BE>(p);
    case PType::I32: return load<int32_t, BE>(p);
    case PType::U32: return load<uint32_t, BE>(p);
    case PType::F32: return load<float, BE>(p);
    case PType::F64: return load<double, BE>(p);
  }
  return 0;
}

template <class T, bool BE>
void decode_column_typed(const uint8_t* base, size_t record, size_t n, const Sink& s) {
  if (s.d) {
    for (size_t i = 0; i < n; ++i)
      s.d[i * s.stride + s.comp] = static_cast<double>(load<T, BE>(base + i * record));
  } else if (s.f) {
    for (size_t i = 0; i < n; ++i)
      s.f[i * s.stride + s.comp] = narrow_float(static_cast<double>(load<T, BE>(base + i * record)));
  }
}

template <bool BE>
void decode_column(PType t, const uint8_t* base, size_t record, size_t n, const Sink& s) {
  switch (t) {
    case PType::I8: decode_column_typed<int8_t, BE>(base, record, n, s); break;
    case PType::U8: decode_column_typed<uint8_t, BE>(base, record, n, s); break;
    case PType::I16: decode_column_typed<int16_t, BE>(base, record, n, s); break;
    case PType::U16: decode_column_typed<uint16_t, BE>(base, record, n, s); break;
    case PType::I32: decode_column_typed<int32_t, BE>(base, record, n, s); break;
    case PType::U32: decode_column_typed<uint32_t, BE>(base, record, n, s); break;
    case PType::F32: decode_column_typed<float, BE>(base, record, n, s); break;
    case PType::F64: decode_column_typed<double, BE>(base, record, n, s); break;
  }
}

bool is_space(uint8_t c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// How a vertex property is stored in PointData.
enum class Role { Skip, Position, Normal, Color, Alpha, Intensity, Classification, Other };

struct VertexPlan {
  std::vector<Role> role;        // per vertex property
  std::vector<int> comp;         // component for Position / Normal / Color
  std::vector<size_t> other_idx; // index into others for Role::Other
  std::vector<std::string> others;
  std::vector<PType> other_types;  // kept in the output (doubles while decoding)
  PType color_type = PType::U8;
  PType alpha_type = PType::U8;
  bool has_normals = false, has_colors = false, has_alpha = false;
  bool has_intensity = false, has_classification = false;
};

class PlyReader : private io::ReaderBase {
 public:
  using ReaderBase::ReaderBase;
  PointData read();

 private:
  void parse_header();
  void plan_vertex();
  template <bool BE>
  void read_binary(PointData& out);
  void read_ascii(PointData& out);
  void allocate(PointData& out, uint64_t n);
  void finish(PointData& out);
  Sink sink_for(size_t prop);


  Encoding encoding_ = Encoding::Ascii;
  std::vector<Element> elements_;
  size_t vertex_index_ = 0;
  size_t data_start_ = 0;
  std::vector<std::string> comments_;
  VertexPlan plan_;

  // Decoding targets.
  double* positions_ = nullptr;
  std::vector<float> normals_, colors_, alpha_, intensity_, classification_;
  std::vector<std::vector<double>> others_;
};

void PlyReader::parse_header() {
  if (size_ == 0) fail("file is empty (0 bytes)");
  // "ply", then optional spaces or tabs (some writers leave them), then the line end.
  size_t magic_end = 3;
  while (magic_end < size_ && (d_[magic_end] == ' ' || d_[magic_end] == '\t')) ++magic_end;
  if (size_ < 4 || std::memcmp(d_, "ply", 3) != 0 || magic_end >= size_ ||
      (d_[magic_end] != '\n' && d_[magic_end] != '\r'))
    fail("not a PLY file: it does not start with the line 'ply'", 0);
  size_t pos = 0;
  bool have_format = false, done = false;
  int line_no = 0;
  while (pos < size_ && !done) {
    const size_t line_start = pos;
    const uint8_t* nl = static_cast<const uint8_t*>(std::memchr(d_ + pos, '\n', size_ - pos));
    size_t line_end = nl ? static_cast<size_t>(nl - d_) : size_;
    pos = nl ? line_end + 1 : size_;
    ++line_no;
    std::string_view line(reinterpret_cast<const char*>(d_ + line_start), line_end - line_start);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
      line.remove_suffix(1);
    // Tokenise on spaces and tabs.
    std::vector<std::string_view> tok;
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
      if (j > i) tok.push_back(line.substr(i, j - i));
      i = j;
    }
    const auto at = static_cast<int64_t>(line_start);
    if (line_no == 1) continue;  // "ply", checked above
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    if (key == "comment" || key == "obj_info") {
      if (key == "comment" && comments_.size() < 32) {
        std::string_view rest = line.substr(std::min(line.size(), size_t{8}));
        comments_.emplace_back(rest);
      }
      continue;
    }
    if (key == "format") {
      if (tok.size() != 3) fail("malformed format line '" + std::string(line) + "'", at);
      if (tok[1] == "ascii")
        encoding_ = Encoding::Ascii;
      else if (tok[1] == "binary_little_endian")
        encoding_ = Encoding::BinaryLE;
      else if (tok[1] == "binary_big_endian")
        encoding_ = Encoding::BinaryBE;
      else
        fail("unknown PLY format '" + std::string(tok[1]) +
                 "' (expected ascii, binary_little_endian or binary_big_endian)",
             at);
      if (tok[2] != "1.0") fail("unsupported PLY version '" + std::string(tok[2]) + "'", at);
      have_format = true;
    } else if (key == "element") {
      if (tok.size() != 3) fail("malformed element line '" + std::string(line) + "'", at);
      Element e;
      e.name = std::string(tok[1]);
      auto r = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != tok[2].data() + tok[2].size())
        fail("element '" + e.name + "' has an invalid count '" + std::string(tok[2]) + "'", at);
      for (const Element& other : elements_)
        if (other.name == e.name) fail("element '" + e.name + "' is declared twice", at);
      elements_.push_back(std::move(e));
    } else if (key == "property") {
      if (elements_.empty()) fail("property declared before any element", at);
      Property p;
      if (tok.size() >= 2 && tok[1] == "list") {
        if (tok.size() != 5) fail("malformed list property line '" + std::string(line) + "'", at);
        p.is_list = true;
        if (!parse_type(tok[2], p.count_type))
          fail("unknown list count type '" + std::string(tok[2]) + "'", at);
        if (!is_integer_type(p.count_type))
          fail("list count type '" + std::string(tok[2]) + "' is not an integer type", at);
        if (!parse_type(tok[3], p.type))
          fail("unknown property type '" + std::string(tok[3]) + "'", at);
        p.name = std::string(tok[4]);
      } else {
        if (tok.size() != 3) fail("malformed property line '" + std::string(line) + "'", at);
        if (!parse_type(tok[1], p.type))
          fail("unknown property type '" + std::string(tok[1]) + "'", at);
        p.name = std::string(tok[2]);
      }
      Element& e = elements_.back();
      for (const Property& q : e.props)
        if (q.name == p.name)
          fail("property '" + p.name + "' is declared twice in element '" + e.name + "'", at);
      e.props.push_back(std::move(p));
    } else if (key == "end_header") {
      done = true;
      data_start_ = pos;
    } else {
      fail("unexpected header line '" + std::string(line.substr(0, 80)) + "'", at);
    }
  }
  if (!done) fail("header has no 'end_header' line; the file is truncated or not a PLY file");
  if (!have_format) fail("header has no 'format' line");
  bool found = false;
  for (size_t i = 0; i < elements_.size(); ++i)
    if (elements_[i].name == "vertex") {
      vertex_index_ = i;
      found = true;
    }
  if (!found) fail("the file has no 'vertex' element, so it contains no points");
}

void PlyReader::plan_vertex() {
  const Element& v = elements_[vertex_index_];
  const size_t np = v.props.size();
  plan_.role.assign(np, Role::Other);
  plan_.comp.assign(np, 0);
  plan_.other_idx.assign(np, 0);
  auto find = [&](std::initializer_list<const char*> names) -> int {
    for (const char* n : names)
      for (size_t i = 0; i < np; ++i)
        if (!v.props[i].is_list && lower(v.props[i].name) == n) return static_cast<int>(i);
    return -1;
  };
  const int xyz[3] = {find({"x"}), find({"y"}), find({"z"})};
  for (int c = 0; c < 3; ++c) {
    if (xyz[c] < 0) {
      for (const Property& p : v.props)
        if (lower(p.name) == std::string(1, "xyz"[c]))
          fail(std::string("vertex property '") + "xyz"[c] + "' is a list, not a scalar");
      fail(std::string("vertex element has no '") + "xyz"[c] +
           "' property; a point cloud needs x, y and z");
    }
    plan_.role[xyz[c]] = Role::Position;
    plan_.comp[xyz[c]] = c;
  }
  const int nrm[3] = {find({"nx", "normal_x"}), find({"ny", "normal_y"}), find({"nz", "normal_z"})};
  if (nrm[0] >= 0 && nrm[1] >= 0 && nrm[2] >= 0) {
    plan_.has_normals = true;
    for (int c = 0; c < 3; ++c) {
      plan_.role[nrm[c]] = Role::Normal;
      plan_.comp[nrm[c]] = c;
    }
  }
  const int col[3] = {find({"red", "diffuse_red", "r"}), find({"green", "diffuse_green", "g"}),
                      find({"blue", "diffuse_blue", "b"})};
  if (col[0] >= 0 && col[1] >= 0 && col[2] >= 0) {
    plan_.has_colors = true;
    plan_.color_type = v.props[col[0]].type;
    for (int c = 0; c < 3; ++c) {
      plan_.role[col[c]] = Role::Color;
      plan_.comp[col[c]] = c;
      // Mixed colour types: use the widest for the range decision.
      if (type_size(v.props[col[c]].type) > type_size(plan_.color_type) ||
          !is_integer_type(v.props[col[c]].type))
        plan_.color_type = v.props[col[c]].type;
    }
  }
  const int alpha = find({"alpha", "diffuse_alpha", "a"});
  if (alpha >= 0 && plan_.role[alpha] == Role::Other) {
    plan_.has_alpha = true;
    plan_.alpha_type = v.props[alpha].type;
    plan_.role[alpha] = Role::Alpha;
  }
  const int inten = find({"intensity", "scalar_intensity"});
  if (inten >= 0 && plan_.role[inten] == Role::Other) {
    plan_.has_intensity = true;
    plan_.role[inten] = Role::Intensity;
  }
  const int cls = find({"classification", "scalar_classification"});
  if (cls >= 0 && plan_.role[cls] == Role::Other) {
    plan_.has_classification = true;
    plan_.role[cls] = Role::Classification;
  }
  static const char* const reserved[] = {"colors", "normals", "alpha", "intensity",
                                         "classification"};
  for (size_t i = 0; i < np; ++i) {
    if (v.props[i].is_list) {
      plan_.role[i] = Role::Skip;
      continue;
    }
    if (plan_.role[i] != Role::Other) continue;
    std::string name = v.props[i].name;
    for (const char* r : reserved)
      if (name == r) name = "ply_" + name;
    plan_.other_idx[i] = plan_.others.size();
    plan_.others.push_back(name);
    plan_.other_types.push_back(v.props[i].type);
  }
}

void PlyReader::allocate(PointData& out, uint64_t n) {
  io::resize_fresh(out.positions, n * 3);
  positions_ = out.positions.data();
  if (plan_.has_normals) io::resize_fresh(normals_, n * 3);
  if (plan_.has_colors) io::resize_fresh(colors_, n * 3);
  if (plan_.has_alpha) alpha_.assign(n, 0.f);
  if (plan_.has_intensity) intensity_.assign(n, 0.f);
  if (plan_.has_classification) classification_.assign(n, 0.f);
  others_.assign(plan_.others.size(), std::vector<double>());
  for (std::vector<double>& o : others_) io::resize_fresh(o, n);
}

Sink PlyReader::sink_for(size_t i) {
  Sink s;
  switch (plan_.role[i]) {
    case Role::Skip: break;
    case Role::Position: s.d = positions_; s.stride = 3; s.comp = plan_.comp[i]; break;
    case Role::Normal: s.f = normals_.data(); s.stride = 3; s.comp = plan_.comp[i]; break;
    case Role::Color: s.f = colors_.data(); s.stride = 3; s.comp = plan_.comp[i]; break;
    case Role::Alpha: s.f = alpha_.data(); break;
    case Role::Intensity: s.f = intensity_.data(); break;
    case Role::Classification: s.f = classification_.data(); break;
    case Role::Other: s.d = others_[plan_.other_idx[i]].data(); break;
  }
  return s;
}

template <bool BE>
void PlyReader::read_binary(PointData& out) {
  size_t pos = data_start_;
  for (size_t ei = 0; ei < elements_.size(); ++ei) {
    const Element& e = elements_[ei];
    const size_t remaining = size_ - pos;
    const size_t min_rec = e.min_record_size();
    if (min_rec > 0 && e.count > remaining / min_rec)
      fail("file is truncated: element '" + e.name + "' declares " + std::to_string(e.count) +
               " records of " + (e.has_list() ? "at least " : std::string()) +
               std::to_string(min_rec) + " bytes, but only " + std::to_string(remaining) +
               " bytes remain",
           static_cast<int64_t>(pos));
    const bool is_vertex = ei == vertex_index_;
    if (is_vertex) allocate(out, e.count);
    if (!e.has_list()) {
      if (is_vertex) {
        size_t off = 0;
        for (size_t pi = 0; pi < e.props.size(); ++pi) {
          const Sink s = sink_for(pi);
          if (s.d || s.f) decode_column<BE>(e.props[pi].type, d_ + pos + off, min_rec, e.count, s);
          off += type_size(e.props[pi].type);
        }
      }
      pos += e.count * min_rec;
      continue;
    }
    // Records with lists: walk one by one.
    std::vector<Sink> sinks;
    if (is_vertex)
      for (size_t pi = 0; pi < e.props.size(); ++pi) sinks.push_back(sink_for(pi));
    for (uint64_t r = 0; r < e.count; ++r) {
      for (size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        if (!p.is_list) {
          const size_t sz = type_size(p.type);
          if (sz > size_ - pos)
            fail("file is truncated inside record " + std::to_string(r) + " of element '" +
                     e.name + "'",
                 static_cast<int64_t>(pos));
          if (is_vertex) sinks[pi].put(r, load_as_double<BE>(p.type, d_ + pos));
          pos += sz;
          continue;
        }
        const size_t csz = type_size(p.count_type);
        if (csz > size_ - pos)
          fail("file is truncated inside record " + std::to_string(r) + " of element '" +
                   e.name + "'",
               static_cast<int64_t>(pos));
        const double cnt = load_as_double<BE>(p.count_type, d_ + pos);
        if (cnt < 0)
          fail("list '" + p.name + "' in record " + std::to_string(r) + " of element '" + e.name +
                   "' has a negative length",
               static_cast<int64_t>(pos));
        pos += csz;
        const uint64_t items = static_cast<uint64_t>(cnt);
        const size_t isz = type_size(p.type);
        if (items > (size_ - pos) / isz)
          fail("file is truncated: list '" + p.name + "' in record " + std::to_string(r) +
                   " of element '" + e.name + "' declares " + std::to_string(items) +
                   " items, more than remain in the file",
               static_cast<int64_t>(pos - csz));
        pos += items * isz;
      }
    }
  }
  if (pos < size_) out.metadata["trailing_bytes"] = static_cast<int64_t>(size_ - pos);
}

void PlyReader::read_ascii(PointData& out) {
  size_t pos = data_start_;
  // Next whitespace-separated token, or empty at end of file.
  auto next_token = [&](std::string_view& tok) -> bool {
    while (pos < size_ && is_space(d_[pos])) ++pos;
    if (pos >= size_) return false;
    size_t start = pos;
    while (pos < size_ && !is_space(d_[pos])) ++pos;
    tok = std::string_view(reinterpret_cast<const char*>(d_ + start), pos - start);
    return true;
  };
  auto parse_number = [&](std::string_view tok, double& v) -> bool {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b < e && *b == '+') ++b;
    auto r = std::from_chars(b, e, v);
    return r.ec == std::errc() && r.ptr == e;
  };
  for (size_t ei = 0; ei < elements_.size(); ++ei) {
    const Element& e = elements_[ei];
    const bool is_vertex = ei == vertex_index_;
    if (e.props.empty()) continue;  // no values, whatever the count
    // Each value needs at least one character and one separator.
    const size_t remaining = size_ - pos;
    if (!e.props.empty() && e.count > (remaining + 1) / (2 * e.props.size()))
      fail("file is truncated: element '" + e.name + "' declares " + std::to_string(e.count) +
               " records of " + std::to_string(e.props.size()) +
               " values, more than the remaining " + std::to_string(remaining) +
               " bytes can hold",
           static_cast<int64_t>(pos));
    std::vector<Sink> sinks;
    if (is_vertex) {
      allocate(out, e.count);
      for (size_t pi = 0; pi < e.props.size(); ++pi) sinks.push_back(sink_for(pi));
    }
    std::string_view tok;
    for (uint64_t r = 0; r < e.count; ++r) {
      for (size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        if (!next_token(tok))
          fail("file is truncated: element '" + e.name + "' ends after " + std::to_string(r) +
                   " of " + std::to_string(e.count) + " records",
               static_cast<int64_t>(size_));
        const int64_t at = static_cast<int64_t>(pos - tok.size());
        if (!p.is_list) {
          if (is_vertex && sinks[pi].d == nullptr && sinks[pi].f == nullptr) continue;
          if (!is_vertex) continue;
          double v;
          if (!parse_number(tok, v))
            fail("invalid number '" + std::string(tok.substr(0, 40)) + "' for property '" +
                     p.name + "' in record " + std::to_string(r) + " of element '" + e.name + "'",
                 at);
          if (is_integer_type(p.type) && !fits_integer(p.type, v))
            fail("value '" + std::string(tok.substr(0, 40)) + "' of property '" + p.name +
                     "' in record " + std::to_string(r) + " of element '" + e.name +
                     "' is not an integer in the range of its type",
                 at);
          sinks[pi].put(r, v);
          continue;
        }
        uint64_t items = 0;
        auto res = std::from_chars(tok.data(), tok.data() + tok.size(), items);
        if (res.ec != std::errc() || res.ptr != tok.data() + tok.size())
          fail("invalid list length '" + std::string(tok.substr(0, 40)) + "' for list '" +
                   p.name + "' in record " + std::to_string(r) + " of element '" + e.name + "'",
               at);
        for (uint64_t k = 0; k < items; ++k)
          if (!next_token(tok))
            fail("file is truncated inside list '" + p.name + "' of record " + std::to_string(r) +
                     " of element '" + e.name + "'",
                 static_cast<int64_t>(size_));
      }
    }
  }
  // MeshLab/VCG can write more vertex lines than the header declares: the
  // declared records are read, the rest is ignored and said so.
  std::string_view tok;
  if (next_token(tok)) {
    const size_t extra_start = pos - tok.size();
    size_t lines = 1;
    for (size_t i = extra_start; i < size_; ++i) lines += d_[i] == '\n' && i + 1 < size_;
    out.metadata["trailing_bytes"] = static_cast<int64_t>(size_ - extra_start);
    out.metadata["warning"] = "ignored " + std::to_string(size_ - extra_start) + " bytes (" + std::to_string(lines) +
                              " lines) after the last element declared in the header";
  }
}

uint8_t to_u8(float v) {
  if (!(v > 0.f)) return 0;
  if (v >= 255.f) return 255;
  return static_cast<uint8_t>(std::lround(v));
}

// Converts colour/alpha values read as float to 8-bit according to the
// source type: 8-bit as is, 16-bit scaled, floats in [0,1] scaled by 255,
// anything else clamped to [0,255].
void to_8bit(const std::vector<float>& src, PType type, uint8_t* dst) {
  float scale = 1.f;
  if (type == PType::U16 || type == PType::I16) {
    scale = 255.f / 65535.f;
  } else if (type == PType::F32 || type == PType::F64) {
    float maxv = 0.f;
    for (float v : src)
      if (v > maxv) maxv = v;
    if (maxv <= 1.f) scale = 255.f;
  }
  for (size_t i = 0; i < src.size(); ++i) dst[i] = to_u8(src[i] * scale);
}

void PlyReader::finish(PointData& out) {
  if (plan_.has_normals) {
    auto& v = out.add<float>("normals", 3);
    v = std::move(normals_);
  }
  if (plan_.has_colors) {
    auto& v = out.add<uint8_t>("colors", 3);
    to_8bit(colors_, plan_.color_type, v.data());
  }
  if (plan_.has_alpha) {
    auto& v = out.add<uint8_t>("alpha");
    to_8bit(alpha_, plan_.alpha_type, v.data());
  }
  if (plan_.has_intensity) {
    auto& v = out.add<float>("intensity");
    v = std::move(intensity_);
  }
  if (plan_.has_classification) {
    auto& v = out.add<uint8_t>("classification");
    for (size_t i = 0; i < v.size(); ++i) v[i] = to_u8(classification_[i]);
  }
  // Other properties keep their type (values were range-checked on input).
  for (size_t k = 0; k < plan_.others.size(); ++k) {
    const std::vector<double>& src = others_[k];
    auto convert = [&](auto tag) {
      using T = decltype(tag);
      auto& v = out.add<T>(plan_.others[k]);
      for (size_t i = 0; i < src.size(); ++i) {
        if constexpr (std::is_same_v<T, float>)
          v[i] = narrow_float(src[i]);
        else
          v[i] = static_cast<T>(src[i]);
      }
    };
    switch (plan_.other_types[k]) {
      case PType::I8: convert(int8_t{}); break;
      case PType::U8: convert(uint8_t{}); break;
      case PType::I16: convert(int16_t{}); break;
      case PType::U16: convert(uint16_t{}); break;
      case PType::I32: convert(int32_t{}); break;
      case PType::U32: convert(uint32_t{}); break;
      case PType::F32: convert(float{}); break;
      case PType::F64: {
        auto& v = out.add<double>(plan_.others[k]);
        v = std::move(others_[k]);
        break;
      }
    }
  }
}

PointData PlyReader::read() {
  parse_header();
  plan_vertex();
  PointData out;
  switch (encoding_) {
    case Encoding::Ascii: read_ascii(out); break;
    case Encoding::BinaryLE: read_binary<false>(out); break;
    case Encoding::BinaryBE: read_binary<true>(out); break;
  }
  finish(out);
  auto& md = out.metadata;
  md["format"] = std::string("ply");
  md["version"] = std::string("1.0");
  md["encoding"] = std::string(encoding_ == Encoding::Ascii      ? "ascii"
                               : encoding_ == Encoding::BinaryLE ? "binary_little_endian"
                                                                 : "binary_big_endian");
  md["point_count"] = static_cast<int64_t>(elements_[vertex_index_].count);
  std::string names;
  for (const Element& e : elements_) names += (names.empty() ? "" : " ") + e.name;
  md["elements"] = names;
  if (!comments_.empty()) {
    std::string c;
    for (const std::string& s : comments_) c += (c.empty() ? "" : "\n") + s;
    md["comments"] = c;
  }
  out.drop_nonfinite_points();
  io::convert_3dgs_ply(out, path_);  // 3D Gaussian splats: f_dc_*, opacity, scale_*, rot_* (io/gaussians.h)
  return out;
}

}  // namespace

PointData read_ply(const std::string& path) {
  PlyReader reader(path);
  return reader.read();
}

PointData read_ply_memory(const uint8_t* data, size_t size, const std::string& name) {
  PlyReader reader(name, data, size);
  return reader.read();
}

}  // namespace pointnpr
