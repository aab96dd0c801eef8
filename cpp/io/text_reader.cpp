// Delimited text point files (.xyz .pts .txt .csv .asc): one point per line,
// values separated by spaces, tabs, commas or semicolons. An optional first
// line names the columns (quoted or not, CloudCompare's "//X Y Z" too);
// without one, columns are x y z followed by intensity (4 columns), colour
// or normals (6), intensity + colour for Leica .pts (7). A .pts point count
// line is skipped. Comment lines start with '#'.
#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {
namespace {

bool is_sep(char c) { return c == ' ' || c == '\t' || c == ',' || c == ';' || c == '\r'; }

void tokenize(std::string_view line, std::vector<std::string_view>& tok) {
  tok.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_sep(line[i])) ++i;
    if (i >= line.size()) break;
    size_t j = i;
    if (line[i] == '"' || line[i] == '\'') {  // quoted token
      const char q = line[i];
      j = i + 1;
      while (j < line.size() && line[j] != q) ++j;
      tok.push_back(line.substr(i + 1, j - i - 1));
      i = j + 1;
      continue;
    }
    while (j < line.size() && !is_sep(line[j])) ++j;
    tok.push_back(line.substr(i, j - i));
    i = j;
  }
}

bool parse_double(std::string_view s, double& v) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b < e && *b == '+') ++b;
  auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

std::string lower(std::string_view s) {
  std::string r(s);
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

enum class Role { Position, Normal, Color, Intensity, Classification, Other };

uint8_t to_u8(double v) {
  if (!(v > 0)) return 0;
  if (v >= 255) return 255;
  return static_cast<uint8_t>(std::lround(v));
}

PointData read_text_file(const io::MappedFile& file) {
  const std::string& path = file.path();
  const char* d = reinterpret_cast<const char*>(file.data());
  const size_t size = file.size();
  auto fail = [&](const std::string& reason, int64_t at = -1) -> void {
    throw ReadError(path, io::printable(reason), at);
  };
  if (size == 0) fail("file is empty (0 bytes)");
  const std::string ext = io::file_extension(path);

  std::vector<std::string> names;
  std::vector<double> values;  // row-major, ncols per point
  size_t ncols = 0;
  size_t line_no = 0;
  bool pts_count_skipped = false;
  std::vector<std::string_view> tok;
  size_t pos = 0;
  while (pos < size) {
    const size_t start = pos;
    const char* nl = static_cast<const char*>(std::memchr(d + pos, '\n', size - pos));
    const size_t end = nl ? static_cast<size_t>(nl - d) : size;
    pos = nl ? end + 1 : size;
    ++line_no;
    std::string_view line(d + start, end - start);
    tokenize(line, tok);
    if (tok.empty() || tok[0].starts_with("#")) continue;
    const bool header_candidate = values.empty() && names.empty();
    if (header_candidate && tok[0].starts_with("//")) {  // CloudCompare: //X Y Z ...
      tok[0].remove_prefix(2);
      if (tok[0].empty()) tok.erase(tok.begin());
    }
    // Numbers?
    size_t numeric = 0;
    double v;
    for (std::string_view t : tok) numeric += parse_double(t, v) ? 1 : 0;
    if (numeric != tok.size()) {
      if (header_candidate && numeric == 0) {
        for (std::string_view t : tok) names.push_back(lower(t));
        continue;
      }
      for (std::string_view t : tok)
        if (!parse_double(t, v))
          fail("line " + std::to_string(line_no) + ": '" + std::string(t.substr(0, 40)) +
                   "' is not a number",
               static_cast<int64_t>(t.data() - d));
    }
    if (values.empty() && !pts_count_skipped && tok.size() == 1 && ncols == 0) {
      pts_count_skipped = true;  // Leica .pts: the point count on a line of its own
      continue;
    }
    if (ncols == 0) {
      ncols = tok.size();
      if (ncols < 3)
        fail("line " + std::to_string(line_no) + " has " + std::to_string(ncols) +
                 " values; a point needs at least x, y and z",
             static_cast<int64_t>(start));
      if (!names.empty() && names.size() != ncols)
        fail("the header line names " + std::to_string(names.size()) +
                 " columns but the first data line (line " + std::to_string(line_no) + ") has " +
                 std::to_string(ncols) + " values");
    } else if (tok.size() != ncols) {
      fail("line " + std::to_string(line_no) + " has " + std::to_string(tok.size()) +
               " values, expected " + std::to_string(ncols) + " like the lines before it",
           static_cast<int64_t>(start));
    }
    for (std::string_view t : tok) {
      parse_double(t, v);
      values.push_back(v);
    }
  }
  if (ncols == 0) fail("the file contains no points (no line with numeric x y z values)");
  const size_t n = values.size() / ncols;

  // Column roles.
  std::vector<Role> role(ncols, Role::Other);
  std::vector<int> comp(ncols, 0);
  std::vector<std::string> col_name(ncols);
  auto column_range = [&](size_t c, double& lo, double& hi, bool& integral) {
    lo = INFINITY, hi = -INFINITY, integral = true;
    for (size_t i = 0; i < n; ++i) {
      double x = values[i * ncols + c];
      lo = std::min(lo, x), hi = std::max(hi, x);
      if (x != std::floor(x)) integral = false;
    }
  };
  auto looks_like = [&](size_t first, double lo_ok, double hi_ok, bool need_integral) {
    for (size_t c = first; c < first + 3; ++c) {
      double lo, hi;
      bool integral;
      column_range(c, lo, hi, integral);
      if (lo < lo_ok || hi > hi_ok || (need_integral && !integral)) return false;
    }
    return true;
  };
  if (!names.empty()) {
    auto find = [&](std::initializer_list<const char*> opts) -> int {
      for (const char* o : opts)
        for (size_t c = 0; c < ncols; ++c)
          if (names[c] == o) return static_cast<int>(c);
      return -1;
    };
    const int xyz[3] = {find({"x"}), find({"y"}), find({"z"})};
    for (int c = 0; c < 3; ++c) {
      if (xyz[c] < 0)
        fail(std::string("the header line has no '") + "xyz"[c] + "' column; a point needs x, y and z");
      role[xyz[c]] = Role::Position;
      comp[xyz[c]] = c;
    }
    const int nrm[3] = {find({"nx", "normal_x"}), find({"ny", "normal_y"}), find({"nz", "normal_z"})};
    if (nrm[0] >= 0 && nrm[1] >= 0 && nrm[2] >= 0)
      for (int c = 0; c < 3; ++c) role[nrm[c]] = Role::Normal, comp[nrm[c]] = c;
    const int col[3] = {find({"r", "red"}), find({"g", "green"}), find({"b", "blue"})};
    if (col[0] >= 0 && col[1] >= 0 && col[2] >= 0)
      for (int c = 0; c < 3; ++c) role[col[c]] = Role::Color, comp[col[c]] = c;
    const int in = find({"intensity", "i", "scalar_intensity"});
    if (in >= 0 && role[in] == Role::Other) role[in] = Role::Intensity;
    const int cl = find({"classification", "class", "scalar_classification"});
    if (cl >= 0 && role[cl] == Role::Other) role[cl] = Role::Classification;
    for (size_t c = 0; c < ncols; ++c) col_name[c] = names[c];
  } else {
    for (int c = 0; c < 3; ++c) role[c] = Role::Position, comp[c] = c;
    for (size_t c = 3; c < ncols; ++c) col_name[c] = "column_" + std::to_string(c);
    if (ncols == 4) {
      role[3] = Role::Intensity;
    } else if (ncols == 7 && ext == ".pts") {
      role[3] = Role::Intensity;
      for (int c = 0; c < 3; ++c) role[4 + c] = Role::Color, comp[4 + c] = c;
    } else if (ncols >= 6) {
      // Unit-length triples are normals; integers in [0,255] or reals in
      // [0,1] otherwise are colours.
      bool unit = n > 0;
      for (size_t i = 0; i < n && unit; ++i) {
        const double* r = &values[i * ncols + 3];
        unit = std::fabs(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - 1.0) < 1e-3;
      }
      if (unit && ncols == 6) {
        for (int c = 0; c < 3; ++c) role[3 + c] = Role::Normal, comp[3 + c] = c;
      } else if (looks_like(3, 0, 255, true) || looks_like(3, 0, 1, false)) {
        for (int c = 0; c < 3; ++c) role[3 + c] = Role::Color, comp[3 + c] = c;
      }
    }
  }

  PointData out;
  io::resize_fresh(out.positions, n * 3);
  bool colors = false, normals = false;
  for (size_t c = 0; c < ncols; ++c) {
    colors |= role[c] == Role::Color;
    normals |= role[c] == Role::Normal;
  }
  std::vector<uint8_t>* col_out = colors ? &out.add<uint8_t>("colors", 3) : nullptr;
  std::vector<float>* nrm_out = normals ? &out.add<float>("normals", 3) : nullptr;
  for (size_t c = 0; c < ncols; ++c) {
    switch (role[c]) {
      case Role::Position:
        for (size_t i = 0; i < n; ++i) out.positions[3 * i + comp[c]] = values[i * ncols + c];
        break;
      case Role::Normal:
        for (size_t i = 0; i < n; ++i) (*nrm_out)[3 * i + comp[c]] = io::narrow_float(values[i * ncols + c]);
        break;
      case Role::Color: break;  // below, all three at once
      case Role::Intensity: {
        auto& v = out.add<float>("intensity");
        for (size_t i = 0; i < n; ++i) v[i] = io::narrow_float(values[i * ncols + c]);
        break;
      }
      case Role::Classification: {
        auto& v = out.add<uint8_t>("classification");
        for (size_t i = 0; i < n; ++i) v[i] = to_u8(values[i * ncols + c]);
        break;
      }
      case Role::Other: {
        std::string name = col_name[c];
        while (out.has(name)) name = "text_" + name;
        auto& v = out.add<float>(name);
        for (size_t i = 0; i < n; ++i) v[i] = io::narrow_float(values[i * ncols + c]);
        break;
      }
    }
  }
  if (colors) {
    double maxv = 0;
    for (size_t c = 0; c < ncols; ++c)
      if (role[c] == Role::Color)
        for (size_t i = 0; i < n; ++i) maxv = std::max(maxv, values[i * ncols + c]);
    const double scale = maxv <= 1.0 ? 255.0 : maxv > 255.0 ? 255.0 / 65535.0 : 1.0;
    for (size_t c = 0; c < ncols; ++c)
      if (role[c] == Role::Color)
        for (size_t i = 0; i < n; ++i) (*col_out)[3 * i + comp[c]] = to_u8(values[i * ncols + c] * scale);
  }
  out.metadata["format"] = std::string("text");
  out.metadata["columns"] = static_cast<int64_t>(ncols);
  out.metadata["point_count"] = static_cast<int64_t>(n);
  if (!names.empty()) {
    std::string h;
    for (const std::string& s : names) h += (h.empty() ? "" : " ") + s;
    out.metadata["header"] = h;
  }
  out.drop_nonfinite_points();
  return out;
}

}  // namespace

PointData read_text(const std::string& path) { return read_text_file(io::MappedFile(path)); }

PointData read_text_memory(const uint8_t* data, size_t size, const std::string& name) {
  return read_text_file(io::MappedFile(name, data, size));
}

}  // namespace pointnpr
