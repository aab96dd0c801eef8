// Binary little-endian PLY writer: one vertex element with x/y/z as double
// and one property per attribute component, in the attribute's own type.
//
// Names are chosen so that read_ply gives the attributes back: "colors"
// (uint8 x3) as red/green/blue, "alpha" as alpha, "normals" as nx/ny/nz;
// other multi-component attributes become name_0, name_1, ... PLY has no
// 64-bit integers: those are written as double when every value is exact.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "io/readers.h"
#include "io/writer_util.h"

namespace pointnpr {
namespace {

struct Column {
  const PointAttribute* attr = nullptr;  // null: position
  int comp = 0;
  std::string name;
  const char* type = "double";
  size_t size = 8;
};

const char* ply_type(const AttributeValues& v, size_t& size) {
  switch (v.index()) {
    case 0: size = 1; return "uchar";
    case 1: size = 1; return "char";
    case 2: size = 2; return "ushort";
    case 3: size = 2; return "short";
    case 4: size = 4; return "uint";
    case 5: size = 4; return "int";
    case 8: size = 4; return "float";
    default: size = 8; return "double";  // uint64, int64, double
  }
}

// Names the reader would give a role of its own (compared lower-case).
bool reserved_name(const std::string& lower_name) {
  static const std::set<std::string> names = {
      "x", "y", "z", "nx", "ny", "nz", "normal_x", "normal_y", "normal_z", "red", "green",
      "blue", "r", "g", "b", "a", "diffuse_red", "diffuse_green", "diffuse_blue", "alpha",
      "diffuse_alpha", "intensity", "scalar_intensity", "classification",
      "scalar_classification", "colors", "normals"};
  return names.count(lower_name) > 0;
}

std::string sanitize(const std::string& name) {
  std::string s;
  for (unsigned char c : name)
    s += (std::isalnum(c) || c == '_' || c == '-' || c == '.') ? static_cast<char>(c) : '_';
  return s.empty() ? std::string("attr") : s;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

template <class T>
void put_column(const std::vector<T>& v, int comps, int comp, size_t begin, size_t end,
                uint8_t* out, size_t record, size_t offset) {
  for (size_t i = begin; i < end; ++i) {
    const size_t k = i * static_cast<size_t>(comps) + static_cast<size_t>(comp);
    if constexpr (io::is_64bit_integer<T>) {
      const double d = static_cast<double>(v[k]);
      std::memcpy(out + (i - begin) * record + offset, &d, sizeof(d));
    } else {
      std::memcpy(out + (i - begin) * record + offset, &v[k], sizeof(T));
    }
  }
}

}  // namespace

void write_ply(const std::string& path, const PointData& data) {
  io::check_point_data(path, data);
  const size_t n = data.num_points();

  std::vector<Column> cols;
  for (int c = 0; c < 3; ++c) cols.push_back(Column{nullptr, c, std::string(1, "xyz"[c])});
  std::set<std::string> used = {"x", "y", "z"};
  auto add = [&](const PointAttribute& a, int comp, std::string name) {
    Column col{&a, comp, std::move(name)};
    col.type = ply_type(a.values, col.size);
    used.insert(lower(col.name));
    cols.push_back(std::move(col));
  };
  // The standard attributes first, under the names the reader maps back.
  const PointAttribute* colors = data.find("colors");
  const bool std_colors = colors && colors->components == 3 && colors->values.index() == 0;
  const PointAttribute* normals = data.find("normals");
  const bool std_normals = normals && normals->components == 3;
  for (const PointAttribute& a : data.attributes) {
    if (&a == colors && std_colors) {
      add(a, 0, "red"), add(a, 1, "green"), add(a, 2, "blue");
    } else if (&a == normals && std_normals) {
      add(a, 0, "nx"), add(a, 1, "ny"), add(a, 2, "nz");
    } else if (a.components == 1 &&
               (a.name == "alpha" || a.name == "intensity" || a.name == "classification") &&
               !used.count(a.name)) {
      add(a, 0, a.name);
    }
  }
  for (const PointAttribute& a : data.attributes) {
    if ((&a == colors && std_colors) || (&a == normals && std_normals)) continue;
    if (a.components == 1 &&
        (a.name == "alpha" || a.name == "intensity" || a.name == "classification"))
      if (std::any_of(cols.begin(), cols.end(), [&](const Column& c) { return c.attr == &a; }))
        continue;
    // 64-bit integers go out as double: refuse values a double cannot hold.
    std::visit(
        [&](const auto& v) {
          using T = typename std::decay_t<decltype(v)>::value_type;
          if constexpr (io::is_64bit_integer<T>) {
            for (size_t k = 0; k < v.size(); ++k)
              if (static_cast<T>(static_cast<double>(v[k])) != v[k] ||
                  static_cast<double>(v[k]) >= 9.2e18)
                throw Error(path + ": attribute '" + a.name + "' value " + std::to_string(v[k]) +
                            " cannot be written to PLY exactly (PLY has no 64-bit integers)");
          }
        },
        a.values);
    for (int c = 0; c < a.components; ++c) {
      std::string base = sanitize(a.components == 1 ? a.name : a.name + "_" + std::to_string(c));
      std::string name = base;
      while (used.count(lower(name)) || reserved_name(lower(name))) name = "attr_" + name;
      add(a, c, name);
    }
  }

  std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by PointNPR\n";
  if (auto it = data.metadata.find("comments"); it != data.metadata.end())
    if (const auto* text = std::get_if<std::string>(&it->second)) {
      size_t start = 0;
      while (start <= text->size()) {
        size_t end = text->find('\n', start);
        if (end == std::string::npos) end = text->size();
        std::string line = text->substr(start, end - start);
        for (char& ch : line)
          if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F) ch = ' ';
        if (line != "written by PointNPR") header += "comment " + line + "\n";
        start = end + 1;
      }
    }
  header += "element vertex " + std::to_string(n) + "\n";
  size_t record = 0;
  std::vector<size_t> offsets;
  for (const Column& c : cols) {
    header += std::string("property ") + c.type + " " + c.name + "\n";
    offsets.push_back(record);
    record += c.size;
  }
  header += "end_header\n";

  io::OutputFile out(path);
  out.write(header);
  constexpr size_t kChunk = 1 << 14;
  std::vector<uint8_t> buf(kChunk * record);
  for (size_t begin = 0; begin < n; begin += kChunk) {
    const size_t end = std::min(n, begin + kChunk);
    for (size_t ci = 0; ci < cols.size(); ++ci) {
      const Column& c = cols[ci];
      if (!c.attr)
        put_column(data.positions, 3, c.comp, begin, end, buf.data(), record, offsets[ci]);
      else
        std::visit(
            [&](const auto& v) {
              put_column(v, c.attr->components, c.comp, begin, end, buf.data(), record,
                         offsets[ci]);
            },
            c.attr->values);
    }
    out.write(buf.data(), (end - begin) * record);
  }
  out.commit();
}

}  // namespace pointnpr
