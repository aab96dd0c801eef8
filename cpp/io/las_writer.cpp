// LAS 1.4 writer, point data record format 6 (no colour), 7 (colour) or
// 8 (colour + near infrared), chosen from the attributes present.
//
// Coordinates: when the metadata's "scale"/"offset" (a LAS source) hold every
// point exactly, they are kept, so LAS -> LAS is lossless. Otherwise the
// offset is the rounded centre of the bounds and the scale the finest power
// of ten (1e-9 at best, 1e-4 unless the extent exceeds ~429 km) whose integer
// range covers the extent, preferring 0.01 or 0.001 when they hold every
// point exactly. The error is at most scale / 2 per axis.
//
// Standard fields are taken from the attributes of the same name
// (intensity, return_number, number_of_returns, classification, user_data,
// scan_angle in degrees, point_source_id, gps_time, colors as 8-bit (x257) or
// 16-bit, nir); values are rounded to the field's integer and must lie in
// its range. Every other attribute is written as extra bytes, described in
// an extra-bytes VLR. metadata "crs_wkt" becomes an OGC WKT VLR (global
// encoding WKT bit set), "crs_epsg" a GeoKeyDirectory VLR.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "io/readers.h"
#include "io/mapped_file.h"
#include "io/writer_util.h"

namespace pointnpr {
namespace {

constexpr size_t kHeaderSize = 375;

struct Buffer {
  std::string s;
  template <class T>
  Buffer& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
  Buffer& text(const std::string& t, size_t width) {
    std::string f = t.substr(0, width);
    f.resize(width, '\0');
    s += f;
    return *this;
  }
};

template <class T>
void poke(uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}

std::string vlr(const std::string& user, uint16_t id, const std::string& description,
                const std::string& payload) {
  Buffer b;
  b.put<uint16_t>(0).text(user, 16).put<uint16_t>(id);
  b.put<uint16_t>(static_cast<uint16_t>(payload.size())).text(description, 32);
  return b.s + payload;
}

std::string evlr(const std::string& user, uint16_t id, const std::string& description,
                 const std::string& payload) {
  Buffer b;
  b.put<uint16_t>(0).text(user, 16).put<uint16_t>(id);
  b.put<uint64_t>(payload.size()).text(description, 32);
  return b.s + payload;
}

// Extra-bytes base type (1..10) of an attribute's values.
int extra_base_type(const AttributeValues& v) {
  switch (v.index()) {
    case 0: return 1;   // uint8
    case 1: return 2;   // int8
    case 2: return 3;   // uint16
    case 3: return 4;   // int16
    case 4: return 5;   // uint32
    case 5: return 6;   // int32
    case 6: return 7;   // uint64
    case 7: return 8;   // int64
    case 8: return 9;   // float
    default: return 10; // double
  }
}

// One extra-bytes field: an attribute, or `comp` of one when it has more
// than 3 components (LAS extra bytes hold at most 3).
struct ExtraOut {
  const PointAttribute* attr;
  int first_comp;
  int comps;
  std::string name;
  size_t elem_size;
  size_t offset;  // within the record
};

const std::set<std::string>& standard_names() {
  static const std::set<std::string> s = {"intensity",       "return_number", "number_of_returns",
                                          "classification",  "user_data",     "scan_angle",
                                          "point_source_id", "gps_time",      "colors",
                                          "nir"};
  return s;
}

// Rounds attribute values to an integer field, refusing what does not fit.
struct IntField {
  const PointAttribute* attr = nullptr;
  double lo = 0, hi = 0;
  double divide = 1;  // scan angle: degrees / 0.006
  const std::string* path = nullptr;
  int64_t get(size_t k) const {
    const double v = io::value_as_double(*attr, k) / divide;
    const double r = std::nearbyint(v);
    if (!(r >= lo && r <= hi)) {
      char value[32];
      std::snprintf(value, sizeof value, "%.10g", v * divide);
      throw Error(*path + ": attribute '" + attr->name + "' has the value " + value +
                  " at point " +
                  std::to_string(k / static_cast<size_t>(attr->components)) +
                  ", which the LAS field cannot hold (" +
                  (divide == 1 ? std::to_string(static_cast<int64_t>(lo)) + " to " +
                                     std::to_string(static_cast<int64_t>(hi))
                               : std::string("-196.6 to 196.6 degrees")) +
                  ")");
    }
    return static_cast<int64_t>(r);
  }
};

bool metadata_triple(const PointData& d, const char* key, double out[3]) {
  auto it = d.metadata.find(key);
  if (it == d.metadata.end()) return false;
  const auto* v = std::get_if<std::vector<double>>(&it->second);
  if (!v || v->size() != 3) return false;
  for (int c = 0; c < 3; ++c) out[c] = (*v)[c];
  return true;
}

// Whether every coordinate of axis c is exactly k * scale + offset with k in int32.
bool holds_exactly(const std::vector<double>& pos, int c, double scale, double offset) {
  if (!(scale > 0) || !std::isfinite(scale) || !std::isfinite(offset)) return false;
  const size_t n = pos.size() / 3;
  for (size_t i = 0; i < n; ++i) {
    const double p = pos[3 * i + static_cast<size_t>(c)];
    const double k = std::nearbyint((p - offset) / scale);
    if (!(std::fabs(k) <= 2147483647.0)) return false;
    if (k * scale + offset != p) return false;
  }
  return true;
}

}  // namespace

void write_las(const std::string& path, const PointData& data) {
  io::check_point_data(path, data);
  const size_t n = data.num_points();
  const std::vector<double>& pos = data.positions;

  // ---- scale and offset per axis
  double scale[3], offset[3];
  double md_scale[3], md_offset[3];
  const bool have_md = metadata_triple(data, "scale", md_scale) &&
                       metadata_triple(data, "offset", md_offset);
  for (int c = 0; c < 3; ++c) {
    if (have_md && holds_exactly(pos, c, md_scale[c], md_offset[c])) {
      scale[c] = md_scale[c];
      offset[c] = md_offset[c];
      continue;
    }
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (size_t i = 0; i < n; ++i) {
      lo = std::min(lo, pos[3 * i + static_cast<size_t>(c)]);
      hi = std::max(hi, pos[3 * i + static_cast<size_t>(c)]);
    }
    if (n == 0) lo = hi = 0;
    const double o = std::nearbyint(lo / 2 + hi / 2);
    const double reach = std::max(std::fabs(hi - o), std::fabs(lo - o));
    double s = 1e-9;
    int exponent = -9;
    while (reach / s > 2147483000.0) {
      ++exponent;
      s = std::pow(10.0, exponent);
    }
    // A coarser, conventional grid when it holds the data exactly, with
    // offset 0 (when the extent allows) or the centre.
    double chosen_offset = o;
    bool nice_found = false;
    for (double nice : {0.01, 0.001, 0.0001}) {
      if (!(nice > s)) continue;
      for (double candidate : {0.0, o})
        if (holds_exactly(pos, c, nice, candidate)) {
          s = nice;
          chosen_offset = candidate;
          nice_found = true;
          break;
        }
      if (nice_found) break;
    }
    scale[c] = s;
    offset[c] = chosen_offset;
  }

  // ---- standard fields
  auto attr = [&](const char* name, int comps) -> const PointAttribute* {
    const PointAttribute* a = data.find(name);
    return a && a->components == comps ? a : nullptr;
  };
  const PointAttribute* colors = attr("colors", 3);
  if (colors && colors->values.index() != 0 && colors->values.index() != 2)
    colors = nullptr;  // only 8- or 16-bit integer colour is LAS colour
  const PointAttribute* nir = attr("nir", 1);
  const int pf = nir ? 8 : colors ? 7 : 6;
  const size_t base_len = pf == 8 ? 38 : pf == 7 ? 36 : 30;

  auto int_field = [&](const char* name, double lo, double hi, double divide = 1) {
    IntField f;
    f.attr = attr(name, 1);
    f.lo = lo, f.hi = hi, f.divide = divide, f.path = &path;
    return f;
  };
  const IntField intensity = int_field("intensity", 0, 65535);
  const IntField ret = int_field("return_number", 0, 15);
  const IntField nret = int_field("number_of_returns", 0, 15);
  const IntField cls = int_field("classification", 0, 255);
  const IntField user = int_field("user_data", 0, 255);
  const IntField angle = int_field("scan_angle", -32768, 32767, 0.006);
  const IntField source = int_field("point_source_id", 0, 65535);
  const IntField nir_f = int_field("nir", 0, 65535);
  const PointAttribute* gps = attr("gps_time", 1);
  const bool colors_8bit = colors && colors->values.index() == 0;

  // ---- extra bytes
  std::vector<ExtraOut> extra;
  std::set<std::string> names;
  size_t record = base_len;
  for (const PointAttribute& a : data.attributes) {
    const bool is_standard = (&a == colors) || (&a == nir) || (&a == gps) ||
                             (a.components == 1 && standard_names().count(a.name) &&
                              a.name != "colors" && a.name != "nir" && a.name != "gps_time");
    if (is_standard) continue;
    const size_t elem = std::visit([](const auto& v) { return sizeof(v[0]); }, a.values);
    for (int first = 0; first < a.components; first += 3) {
      const int comps = std::min(3, a.components - first);
      std::string base = a.components <= 3 ? a.name : a.name + "_" + std::to_string(first / 3);
      if (base.empty()) base = "extra";
      std::string name = base.substr(0, 32);
      for (int k = 1; names.count(name) || standard_names().count(name); ++k) {
        std::string suffix = std::to_string(k);
        suffix.insert(suffix.begin(), '_');
        name = base.substr(0, 32 - suffix.size());
        name.append(suffix);
      }
      names.insert(name);
      extra.push_back(ExtraOut{&a, first, comps, name, elem, record});
      record += elem * static_cast<size_t>(comps);
    }
  }
  if (record > 65535)
    throw Error(path + ": the attributes need " + std::to_string(record) +
                " bytes per point, more than a LAS point record can hold (65535)");

  // ---- VLRs
  std::string vlrs;
  uint32_t num_vlrs = 0;
  std::string evlrs;
  uint32_t num_evlrs = 0;
  uint16_t global_encoding = 0;
  if (!extra.empty()) {
    Buffer b;
    for (const ExtraOut& e : extra) {
      const int type = extra_base_type(e.attr->values) + 10 * (e.comps - 1);
      b.put<uint16_t>(0).put<uint8_t>(static_cast<uint8_t>(type)).put<uint8_t>(0);
      b.text(e.name, 32);
      b.s.append(4 + 24 * 5, '\0');  // unused, no_data, min, max, scale, offset
      b.text("PointNPR attribute " + e.attr->name, 32);
    }
    if (b.s.size() > 65535)
      throw Error(path + ": too many attributes for the extra bytes VLR");
    vlrs += vlr("LASF_Spec", 4, "Extra bytes", b.s);
    ++num_vlrs;
  }
  if (auto it = data.metadata.find("crs_wkt"); it != data.metadata.end()) {
    if (const auto* wkt = std::get_if<std::string>(&it->second); wkt && !wkt->empty()) {
      const std::string payload = *wkt + std::string(1, '\0');
      if (payload.size() <= 65535) {
        vlrs += vlr("LASF_Projection", 2112, "OGC coordinate system WKT", payload);
        ++num_vlrs;
      } else {
        evlrs += evlr("LASF_Projection", 2112, "OGC coordinate system WKT", payload);
        ++num_evlrs;
      }
      global_encoding |= 16;
    }
  }
  if (auto it = data.metadata.find("crs_epsg"); it != data.metadata.end()) {
    if (const auto* epsg = std::get_if<int64_t>(&it->second); epsg && *epsg > 0 && *epsg < 32767) {
      // GeoKeyDirectory: version 1.1.0, one key: ProjectedCSTypeGeoKey (3072)
      // for projected systems; EPSG geographic codes lie in 4000-4999.
      const uint16_t key = (*epsg >= 4000 && *epsg < 5000) ? 2048 : 3072;
      Buffer g;
      g.put<uint16_t>(1).put<uint16_t>(1).put<uint16_t>(0).put<uint16_t>(1);
      g.put<uint16_t>(key).put<uint16_t>(0).put<uint16_t>(1).put<uint16_t>(
          static_cast<uint16_t>(*epsg));
      vlrs += vlr("LASF_Projection", 34735, "GeoKeyDirectoryTag", g.s);
      ++num_vlrs;
    }
  }

  // ---- header
  const uint64_t point_offset = kHeaderSize + vlrs.size();
  std::array<uint64_t, 15> by_return{};
  double bmin[3], bmax[3];
  for (int c = 0; c < 3; ++c) bmin[c] = bmax[c] = n ? NAN : 0;
  auto quantize = [&](size_t i, int c) {
    return static_cast<int32_t>(
        std::nearbyint((pos[3 * i + static_cast<size_t>(c)] - offset[c]) / scale[c]));
  };
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double q = quantize(i, c) * scale[c] + offset[c];
      if (i == 0 || q < bmin[c]) bmin[c] = q;
      if (i == 0 || q > bmax[c]) bmax[c] = q;
    }
    if (ret.attr) {
      const int64_t r = ret.get(i);
      if (r >= 1) ++by_return[static_cast<size_t>(r - 1)];
    }
  }

  auto md_string = [&](const char* key, const std::string& fallback) {
    auto it = data.metadata.find(key);
    const std::string* s = it == data.metadata.end() ? nullptr : std::get_if<std::string>(&it->second);
    return s ? *s : fallback;
  };
  auto md_u16 = [&](const char* key, int64_t fallback) {
    auto it = data.metadata.find(key);
    const int64_t* v = it == data.metadata.end() ? nullptr : std::get_if<int64_t>(&it->second);
    return static_cast<uint16_t>(v && *v >= 0 && *v <= 65535 ? *v : fallback);
  };
  const std::time_t now = std::time(nullptr);
  std::tm tm_now{};
  gmtime_r(&now, &tm_now);

  Buffer h;
  h.text("LASF", 4).put<uint16_t>(md_u16("file_source_id", 0)).put<uint16_t>(global_encoding);
  h.s.append(16, '\0');  // project GUID
  h.put<uint8_t>(1).put<uint8_t>(4);
  h.text(md_string("system_identifier", "PointNPR"), 32).text("PointNPR 0.1", 32);
  h.put<uint16_t>(md_u16("creation_day", tm_now.tm_yday + 1));
  h.put<uint16_t>(md_u16("creation_year", tm_now.tm_year + 1900));
  h.put<uint16_t>(static_cast<uint16_t>(kHeaderSize));
  if (point_offset > std::numeric_limits<uint32_t>::max())
    throw Error(path + ": VLRs too large for a LAS header");
  h.put<uint32_t>(static_cast<uint32_t>(point_offset)).put<uint32_t>(num_vlrs);
  h.put<uint8_t>(static_cast<uint8_t>(pf)).put<uint16_t>(static_cast<uint16_t>(record));
  h.put<uint32_t>(0);                           // legacy point count (0 for formats 6-10)
  for (int i = 0; i < 5; ++i) h.put<uint32_t>(0);  // legacy points by return
  for (double s : scale) h.put<double>(s);
  for (double o : offset) h.put<double>(o);
  for (int c = 0; c < 3; ++c) h.put<double>(bmax[c]).put<double>(bmin[c]);
  h.put<uint64_t>(0);  // waveform data start
  h.put<uint64_t>(num_evlrs ? point_offset + static_cast<uint64_t>(n) * record : 0);
  h.put<uint32_t>(num_evlrs);
  h.put<uint64_t>(n);
  for (uint64_t c : by_return) h.put<uint64_t>(c);
  if (h.s.size() != kHeaderSize) throw Error(path + ": internal error: LAS header size");

  io::OutputFile out(path);
  out.write(h.s);
  out.write(vlrs);

  // ---- point records, in chunks
  constexpr size_t kChunk = 1 << 14;
  std::vector<uint8_t> buf(kChunk * record);
  for (size_t begin = 0; begin < n; begin += kChunk) {
    const size_t end = std::min(n, begin + kChunk);
    std::fill(buf.begin(), buf.end(), uint8_t{0});
    for (size_t i = begin; i < end; ++i) {
      uint8_t* r = buf.data() + (i - begin) * record;
      for (int c = 0; c < 3; ++c) poke<int32_t>(r + 4 * c, quantize(i, c));
      if (intensity.attr) poke<uint16_t>(r + 12, static_cast<uint16_t>(intensity.get(i)));
      const int64_t rn = ret.attr ? ret.get(i) : 0;
      const int64_t nr = nret.attr ? nret.get(i) : 0;
      r[14] = static_cast<uint8_t>(rn | (nr << 4));
      if (cls.attr) r[16] = static_cast<uint8_t>(cls.get(i));
      if (user.attr) r[17] = static_cast<uint8_t>(user.get(i));
      if (angle.attr) poke<int16_t>(r + 18, static_cast<int16_t>(angle.get(i)));
      if (source.attr) poke<uint16_t>(r + 20, static_cast<uint16_t>(source.get(i)));
      if (gps) poke<double>(r + 22, io::value_as_double(*gps, i));
      if (colors) {
        for (int c = 0; c < 3; ++c) {
          const size_t k = 3 * i + static_cast<size_t>(c);
          const uint16_t v = colors_8bit ? static_cast<uint16_t>(std::get<0>(colors->values)[k] * 257)
                                         : std::get<2>(colors->values)[k];
          poke<uint16_t>(r + 30 + 2 * c, v);
        }
      }
      if (nir_f.attr) poke<uint16_t>(r + 36, static_cast<uint16_t>(nir_f.get(i)));
    }
    for (const ExtraOut& e : extra) {
      std::visit(
          [&](const auto& v) {
            const size_t comps = static_cast<size_t>(e.attr->components);
            for (size_t i = begin; i < end; ++i) {
              uint8_t* r = buf.data() + (i - begin) * record + e.offset;
              std::memcpy(r, &v[i * comps + static_cast<size_t>(e.first_comp)],
                          e.elem_size * static_cast<size_t>(e.comps));
            }
          },
          e.attr->values);
    }
    out.write(buf.data(), (end - begin) * record);
  }
  out.write(evlrs);
  out.commit();
}

void write_point_cloud(const std::string& path, const PointData& data) {
  const std::string ext = io::file_extension(path);
  if (ext == ".ply") return write_ply(path, data);
  if (ext == ".las") return write_las(path, data);
  throw Error(path + ": cannot write '" + ext +
              "' files; the writers produce .ply (binary) and .las (LAS 1.4)");
}

}  // namespace pointnpr
