// ASTM E2807 (E57) reader: every /data3D scan of the file, each as a
// PointData with its pose applied (in double), spherical coordinates turned
// cartesian (in double) and points of an invalid state left out. Written
// from the standard; the layers are e57_pages (header, pages, CRC-32C),
// e57_xml (the XML section) and e57_bitpack (CompressedVector sections).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <set>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/progress.h"
#include "io/e57_bitpack.h"
#include "io/e57_pages.h"
#include "io/e57_xml.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {
namespace {

using e57::FieldCodec;
using e57::FieldKind;
using e57::PagedFile;
using e57::XmlElement;

constexpr int64_t kInt64Min = std::numeric_limits<int64_t>::min();
constexpr int64_t kInt64Max = std::numeric_limits<int64_t>::max();

// The prototype's terminals in document order: the order of the bytestreams.
void collect_fields(const PagedFile& file, const XmlElement& e, const std::string& prefix,
                    std::vector<FieldCodec>& out) {
  for (const XmlElement& c : e.children) {
    const std::string name = prefix.empty() ? c.name : prefix + "/" + c.name;
    FieldCodec f;
    f.name = name;
    if (c.type == "Structure") {
      collect_fields(file, c, name, out);
      continue;
    } else if (c.type == "Float") {
      auto it = c.attributes.find("precision");
      const bool single = it != c.attributes.end() && it->second == "single";
      if (it != c.attributes.end() && it->second != "single" && it->second != "double")
        file.fail("prototype field " + name + " has precision '" + it->second + "'");
      f.kind = single ? FieldKind::Float32 : FieldKind::Float64;
      f.bits = single ? 32 : 64;
    } else if (c.type == "Integer" || c.type == "ScaledInteger") {
      f.kind = c.type == "Integer" ? FieldKind::Integer : FieldKind::ScaledInteger;
      f.minimum = e57::attr_int(file, c, "minimum", kInt64Min);
      f.maximum = e57::attr_int(file, c, "maximum", kInt64Max);
      if (f.minimum > f.maximum)
        file.fail("prototype field " + name + " has minimum " + std::to_string(f.minimum) + " above maximum " +
                  std::to_string(f.maximum));
      f.bits = e57::integer_bits(f.minimum, f.maximum);
      if (f.kind == FieldKind::ScaledInteger) {
        f.scale = e57::attr_double(file, c, "scale", 1.0);
        f.offset = e57::attr_double(file, c, "offset", 0.0);
        if (f.scale == 0.0) file.fail("prototype field " + name + " has a scale of 0");
      }
    } else {
      file.fail("prototype field " + name + " is of type '" + c.type +
                "', which this reader cannot decode in point records (Float, Integer and ScaledInteger)");
    }
    out.push_back(std::move(f));
  }
}

void check_codecs(const PagedFile& file, const XmlElement* codecs) {
  if (!codecs) return;
  for (const XmlElement& c : codecs->children)
    if (!c.child("bitPackCodec"))
      file.fail("a CompressedVector uses a codec other than bitPackCodec (the only one E57 defines)");
}

struct Limits {
  bool present = false;
  double minimum = 0, maximum = 0;
};

Limits limits_of(const PagedFile& file, const XmlElement* parent, const std::string& min_name,
                 const std::string& max_name) {
  Limits l;
  if (!parent || !parent->child(min_name) || !parent->child(max_name)) return l;
  const XmlElement* a = parent->child(min_name);
  const XmlElement* b = parent->child(max_name);
  l.minimum = e57::xml_number(file, a, 0);
  l.maximum = e57::xml_number(file, b, 0);
  l.present = l.maximum > l.minimum;
  return l;
}

// What the prototype itself allows, when the scan gives no limits.
Limits limits_of(const FieldCodec& f) {
  Limits l;
  if (f.kind == FieldKind::Integer) {
    l = {true, static_cast<double>(f.minimum), static_cast<double>(f.maximum)};
  } else if (f.kind == FieldKind::ScaledInteger) {
    l = {true, static_cast<double>(f.minimum) * f.scale + f.offset,
         static_cast<double>(f.maximum) * f.scale + f.offset};
    if (l.minimum > l.maximum) std::swap(l.minimum, l.maximum);
  }
  l.present = l.present && l.maximum > l.minimum;
  return l;
}

struct Pose {
  double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double t[3] = {0, 0, 0};
  double quaternion[4] = {1, 0, 0, 0};  // w, x, y, z as the file gives it
};

Pose pose_of(const PagedFile& file, const XmlElement& scan) {
  Pose p;
  const XmlElement* pose = scan.child("pose");
  if (!pose) return p;
  if (const XmlElement* t = pose->child("translation"))
    for (int i = 0; i < 3; ++i) p.t[i] = e57::xml_number(file, t->child(std::string(1, "xyz"[i])), 0.0);
  if (const XmlElement* q = pose->child("rotation")) {
    double w = e57::xml_number(file, q->child("w"), 1.0), x = e57::xml_number(file, q->child("x"), 0.0),
           y = e57::xml_number(file, q->child("y"), 0.0), z = e57::xml_number(file, q->child("z"), 0.0);
    p.quaternion[0] = w, p.quaternion[1] = x, p.quaternion[2] = y, p.quaternion[3] = z;
    const double norm = std::sqrt(w * w + x * x + y * y + z * z);
    if (!(norm > 0) || !std::isfinite(norm)) file.fail("scan pose has a zero rotation quaternion");
    // The standard asks for a unit quaternion; dividing keeps a slightly
    // off one a rotation rather than a scaling.
    w /= norm, x /= norm, y /= norm, z /= norm;
    const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                         2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    std::copy(r, r + 9, p.r);
  }
  return p;
}

std::string images_report(const XmlElement* images2d) {
  if (!images2d) return {};
  static const char* kinds[] = {"pinholeRepresentation", "sphericalRepresentation",
                                "cylindricalRepresentation", "visualReferenceRepresentation"};
  std::string report;
  for (const XmlElement& image : images2d->children) {
    std::string line = image.child("name") ? image.child("name")->text : std::string("(unnamed)");
    for (const char* kind : kinds) {
      const XmlElement* rep = image.child(kind);
      if (!rep) continue;
      line += std::string(" (") + kind;
      const XmlElement* w = rep->child("imageWidth");
      const XmlElement* h = rep->child("imageHeight");
      if (w && h) line += ", " + w->text + "x" + h->text;
      line += ")";
    }
    report += (report.empty() ? "" : "\n") + line;
  }
  return report;
}

class E57Reader {
 public:
  E57Reader(const std::string& name, const uint8_t* data, size_t size) : file_(name, data, size) {}

  std::vector<PointData> read(bool verify_checksums) {
    if (verify_checksums) file_.verify_checksums();
    const XmlElement root = e57::parse_xml(file_);
    const XmlElement* data3d = root.child("data3D");
    const size_t scans = data3d ? data3d->children.size() : 0;
    coordinate_metadata_ = e57::xml_string(root.child("coordinateMetadata"));
    images_ = images_report(root.child("images2D"));
    images_count_ = root.child("images2D") ? root.child("images2D")->children.size() : 0;
    check_sections_apart(data3d);
    std::vector<PointData> out(scans);
    // The caller's Progress (ProgressScope), handed to the worker threads.
    Progress* progress = current_progress();
    // Scans decode independently; errors are thrown in scan order.
    std::vector<std::exception_ptr> errors(scans);
    tbb::parallel_for(size_t{0}, scans, [&](size_t i) {
      try {
        out[i] = read_scan(data3d->children[i], i, scans, progress);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    });
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
    return out;
  }

 private:
  PointData read_scan(const XmlElement& scan, size_t index, size_t scans, Progress* progress) const;

  // Each scan's records are bounded by its section's bytes; sections that
  // share bytes would let many scans claim the same ones (and allocate for
  // them), so no two may overlap.
  void check_sections_apart(const XmlElement* data3d) const {
    if (!data3d) return;
    std::vector<std::pair<uint64_t, uint64_t>> sections;  // logical [begin, end)
    for (const XmlElement& scan : data3d->children) {
      const XmlElement* points = scan.child("points");
      if (!points || !points->attributes.count("fileOffset")) continue;  // read_scan says why
      const uint64_t begin = file_.to_logical(e57::attr_uint(file_, *points, "fileOffset"));
      uint8_t header[32];
      file_.copy(begin, sizeof(header), header);
      const uint64_t length = io::load_le<uint64_t>(header + 8);
      sections.emplace_back(begin, begin + std::max<uint64_t>(std::min(length, file_.logical_size() - begin), 1));
    }
    std::sort(sections.begin(), sections.end());
    for (size_t i = 1; i < sections.size(); ++i)
      if (sections[i].first < sections[i - 1].second)
        file_.fail("two scans' CompressedVector sections overlap (at logical offsets " +
                       std::to_string(sections[i - 1].first) + " and " + std::to_string(sections[i].first) + ")",
                   static_cast<int64_t>(PagedFile::to_physical(sections[i].first)));
  }

  PagedFile file_;
  std::string coordinate_metadata_;
  std::string images_;
  size_t images_count_ = 0;
};

int find_field(const std::vector<FieldCodec>& fields, const std::string& name) {
  for (size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return static_cast<int>(i);
  return -1;
}

// A double as T without undefined behaviour: integers saturate at T's
// range and NaN becomes 0 (a field of another type than the standard's, or
// out of its declared range, cannot make a cast overflow).
template <class T>
T saturate(double v) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(v);
  } else {
    if (std::isnan(v)) return T{0};
    constexpr double lo = static_cast<double>(std::numeric_limits<T>::min());
    constexpr double hi = static_cast<double>(std::numeric_limits<T>::max());
    if (v <= lo) return std::numeric_limits<T>::min();
    if (v >= hi) return std::numeric_limits<T>::max();
    return static_cast<T>(v);
  }
}

// The attributes a scan is read into, block after block: each appends the
// values of the block's kept rows (`rows`) of its field(s), converted.
struct Outputs {
  using Columns = std::vector<const double*>;
  explicit Outputs(size_t records) : capacity(records) {}

  template <class T, class Convert>
  void column(int field, const std::string& name, Convert convert) {
    names.insert(name);
    auto values = std::make_shared<std::vector<T>>();
    reserve_fresh(*values, capacity);
    appenders.push_back([this, values, field, convert](const Columns& c) {
      const double* col = c[static_cast<size_t>(field)];
      T* o = grow(*values, rows.size());
      for (uint32_t i : rows) *o++ = convert(col[i]);
    });
    finishers.push_back([values, name](PointData& d) { d.set(name, 1, shrunk(std::move(*values))); });
  }

  template <class T, class Convert>
  void triple(std::array<int, 3> fields, const std::string& name, Convert convert) {
    names.insert(name);
    auto values = std::make_shared<std::vector<T>>();
    reserve_fresh(*values, capacity * 3);
    appenders.push_back([this, values, fields, convert](const Columns& c) {
      const double* a = c[static_cast<size_t>(fields[0])];
      const double* b = c[static_cast<size_t>(fields[1])];
      const double* d = c[static_cast<size_t>(fields[2])];
      T* o = grow(*values, 3 * rows.size());
      for (uint32_t i : rows) {
        const double v[3] = {a[i], b[i], d[i]};
        convert(v, o);
        o += 3;
      }
    });
    finishers.push_back([values, name](PointData& d) { d.set(name, 3, shrunk(std::move(*values))); });
  }

  void append(const Columns& c) {
    for (auto& a : appenders) a(c);
  }
  void finish(PointData& d) {
    for (auto& f : finishers) f(d);
  }

  // Capacity for n values, huge pages advised before they are first touched.
  template <class T>
  static void reserve_fresh(std::vector<T>& v, size_t n) {
    v.reserve(n);
    io::advise_huge_pages(v.data(), n * sizeof(T));
  }

  // Room for n more values at the end of v (reserved: no reallocation).
  template <class T>
  static T* grow(std::vector<T>& v, size_t n) {
    const size_t at = v.size();
    v.resize(at + n);
    return v.data() + at;
  }

  // Capacity reserved for every record gives back what invalid points left unused.
  template <class T>
  static std::vector<T> shrunk(std::vector<T>&& v) {
    if (v.size() < v.capacity() / 8 * 7) v.shrink_to_fit();
    return std::move(v);
  }

  size_t capacity;
  std::vector<uint32_t> rows;  // the current block's kept rows
  std::set<std::string> names;  // the attributes planned
  std::vector<std::function<void(const Columns&)>> appenders;
  std::vector<std::function<void(PointData&)>> finishers;
};

uint8_t to_u8(double v, const Limits& l) {
  if (!l.present) return saturate<uint8_t>(v);
  const double unit = (v - l.minimum) / (l.maximum - l.minimum);
  if (!(unit > 0)) return 0;  // NaN too
  if (unit >= 1) return 255;
  return static_cast<uint8_t>(unit * 255.0 + 0.5);  // rounded half up
}

PointData E57Reader::read_scan(const XmlElement& scan, size_t index, size_t scans, Progress* progress) const {
  const std::string label = "scan " + std::to_string(index);
  const XmlElement* points = scan.child("points");
  if (!points || points->type != "CompressedVector") file_.fail(label + " has no CompressedVector 'points'");
  const XmlElement* prototype = points->child("prototype");
  if (!prototype) file_.fail(label + ": its points have no prototype");
  std::vector<FieldCodec> fields;
  collect_fields(file_, *prototype, "", fields);
  check_codecs(file_, points->child("codecs"));
  const uint64_t record_count = e57::attr_uint(file_, *points, "recordCount");
  const uint64_t file_offset = e57::attr_uint(file_, *points, "fileOffset");

  const int cx = find_field(fields, "cartesianX"), cy = find_field(fields, "cartesianY"),
            cz = find_field(fields, "cartesianZ");
  const int sr = find_field(fields, "sphericalRange"), sa = find_field(fields, "sphericalAzimuth"),
            se = find_field(fields, "sphericalElevation");
  const bool cartesian = cx >= 0 && cy >= 0 && cz >= 0;
  const bool spherical = sr >= 0 && sa >= 0 && se >= 0;
  if (!cartesian && !spherical)
    file_.fail(label + " has neither cartesianX/Y/Z nor sphericalRange/Azimuth/Elevation");

  const Pose pose = pose_of(file_, scan);
  // Points whose state says "no position" (2) or "direction only" (1) are left out.
  const int state = find_field(fields, cartesian ? "cartesianInvalidState" : "sphericalInvalidState");
  std::vector<bool> used(fields.size(), false);
  for (int f : {cx, cy, cz, sr, sa, se, state})
    if (f >= 0) used[static_cast<size_t>(f)] = true;

  // The records arrive in blocks (e57::RowBlockSink); each block appends
  // its kept rows to the outputs, reserved for every record up front.
  e57::check_compressed_vector(file_, file_offset, record_count, fields);  // before reserving for its records
  Outputs out(static_cast<size_t>(record_count));
  PointData d;

  if (const int f = find_field(fields, "intensity"); f >= 0) {
    out.column<float>(f, "intensity", [](double v) { return io::narrow_float(v); });
    Limits l = limits_of(file_, scan.child("intensityLimits"), "intensityMinimum", "intensityMaximum");
    if (!l.present) l = limits_of(fields[f]);
    if (l.present) d.metadata["intensity_limits"] = std::vector<double>{l.minimum, l.maximum};
    used[f] = true;
  }
  const int red = find_field(fields, "colorRed"), green = find_field(fields, "colorGreen"),
            blue = find_field(fields, "colorBlue");
  if (red >= 0 && green >= 0 && blue >= 0) {
    const XmlElement* cl = scan.child("colorLimits");
    const std::array<int, 3> channel = {red, green, blue};
    const char* names[3] = {"Red", "Green", "Blue"};
    std::array<Limits, 3> limits;
    std::vector<double> reported;
    for (int c = 0; c < 3; ++c) {
      limits[c] = limits_of(file_, cl, std::string("color") + names[c] + "Minimum",
                            std::string("color") + names[c] + "Maximum");
      if (!limits[c].present) limits[c] = limits_of(fields[channel[c]]);
      reported.push_back(limits[c].minimum), reported.push_back(limits[c].maximum);
      used[channel[c]] = true;
    }
    out.triple<uint8_t>(channel, "colors", [limits](const double v[3], uint8_t o[3]) {
      for (int c = 0; c < 3; ++c) o[c] = to_u8(v[c], limits[c]);
    });
    d.metadata["color_limits"] = std::move(reported);
  }
  const int nx = find_field(fields, "nor:normalX"), ny = find_field(fields, "nor:normalY"),
            nz = find_field(fields, "nor:normalZ");
  if (nx >= 0 && ny >= 0 && nz >= 0) {
    // Normals turn with the scan's pose (no translation).
    out.triple<float>({nx, ny, nz}, "normals", [pose](const double n[3], float o[3]) {
      const double* r = pose.r;
      for (int a = 0; a < 3; ++a) o[a] = io::narrow_float(r[3 * a] * n[0] + r[3 * a + 1] * n[1] + r[3 * a + 2] * n[2]);
    });
    used[nx] = used[ny] = used[nz] = true;
  }
  // Index-like integers keep their values; LAS's return_number counts from 1.
  for (auto [field, attr] : {std::pair{"rowIndex", "row_index"}, std::pair{"columnIndex", "column_index"}}) {
    const int f = find_field(fields, field);
    if (f < 0) continue;
    const FieldCodec& c = fields[f];
    if (c.kind == FieldKind::Integer && c.minimum >= INT32_MIN && c.maximum <= INT32_MAX)
      out.column<int32_t>(f, attr, [](double v) { return saturate<int32_t>(v); });
    else
      out.column<int64_t>(f, attr, [](double v) { return saturate<int64_t>(v); });
    used[f] = true;
  }
  auto take = [&](const char* field, const char* attr, auto convert) {
    using T = decltype(convert(0.0));
    if (const int f = find_field(fields, field); f >= 0) {
      out.column<T>(f, attr, convert);
      used[f] = true;
    }
  };
  take("returnIndex", "return_number", [](double v) { return saturate<uint8_t>(v + 1); });
  take("returnCount", "number_of_returns", [](double v) { return saturate<uint8_t>(v); });
  take("timeStamp", "time_stamp", [](double v) { return v; });
  take("isIntensityInvalid", "intensity_invalid", [](double v) { return saturate<uint8_t>(v); });
  take("isColorInvalid", "color_invalid", [](double v) { return saturate<uint8_t>(v); });
  take("isTimeStampInvalid", "time_stamp_invalid", [](double v) { return saturate<uint8_t>(v); });
  // Any other field, in double (exact for floats and integers up to 2^53).
  for (size_t f = 0; f < fields.size(); ++f)
    if (!used[f] && !out.names.count(fields[f].name))
      out.column<double>(static_cast<int>(f), fields[f].name, [](double v) { return v; });

  std::vector<double> positions;
  Outputs::reserve_fresh(positions, static_cast<size_t>(record_count) * 3);
  const double* r = pose.r;
  e57::decode_compressed_vector(
      file_, file_offset, record_count, fields,
      [&](uint64_t, size_t n, const std::vector<const double*>& c) {
        std::vector<uint32_t>& rows = out.rows;
        rows.clear();
        const double* st = state >= 0 ? c[static_cast<size_t>(state)] : nullptr;
        for (size_t i = 0; i < n; ++i)
          if (!st || st[i] == 0.0) rows.push_back(static_cast<uint32_t>(i));
        double* o = Outputs::grow(positions, 3 * rows.size());
        for (uint32_t i : rows) {
          double p[3];
          if (cartesian) {
            p[0] = c[cx][i], p[1] = c[cy][i], p[2] = c[cz][i];
          } else {
            const double range = c[sr][i], az = c[sa][i], el = c[se][i];
            p[0] = range * std::cos(el) * std::cos(az);
            p[1] = range * std::cos(el) * std::sin(az);
            p[2] = range * std::sin(el);
          }
          for (int a = 0; a < 3; ++a) *o++ = r[3 * a] * p[0] + r[3 * a + 1] * p[1] + r[3 * a + 2] * p[2] + pose.t[a];
        }
        out.append(c);
      },
      progress);
  const size_t kept = positions.size() / 3;
  if (positions.size() < positions.capacity() / 8 * 7) positions.shrink_to_fit();
  d.positions = std::move(positions);
  out.finish(d);

  // As every reader: NaN/inf positions dropped and counted (dropped_nonfinite).
  const size_t nonfinite = d.drop_nonfinite_points();
  d.metadata["format"] = std::string("e57");
  d.metadata["version"] = std::to_string(file_.header().version_major) + "." + std::to_string(file_.header().version_minor);
  d.metadata["point_count"] = static_cast<int64_t>(kept - nonfinite);
  d.metadata["record_count"] = static_cast<int64_t>(record_count);
  if (kept != record_count) d.metadata["dropped_invalid"] = static_cast<int64_t>(record_count - kept);
  d.metadata["scan_index"] = static_cast<int64_t>(index);
  d.metadata["scan_count"] = static_cast<int64_t>(scans);
  d.metadata["scan_name"] = e57::xml_string(scan.child("name"));
  d.metadata["scan_guid"] = e57::xml_string(scan.child("guid"));
  d.metadata["scan_description"] = e57::xml_string(scan.child("description"));
  d.metadata["coordinates"] = std::string(cartesian ? "cartesian" : "spherical");
  d.metadata["pose_rotation"] = std::vector<double>(pose.quaternion, pose.quaternion + 4);
  d.metadata["pose_translation"] = std::vector<double>(pose.t, pose.t + 3);
  d.metadata["coordinate_metadata"] = coordinate_metadata_;
  d.metadata["images2d"] = images_;
  d.metadata["images2d_count"] = static_cast<int64_t>(images_count_);
  return d;
}

}  // namespace

std::vector<PointData> read_e57_scans_memory(const uint8_t* data, size_t size, const std::string& name,
                                             bool verify_checksums) {
  return E57Reader(name, data, size).read(verify_checksums);
}

std::vector<PointData> read_e57_scans(const std::string& path) {
  io::MappedFile file(path);
  return read_e57_scans_memory(file.data(), file.size(), path, true);
}

}  // namespace pointnpr

namespace pointnpr {
namespace {

// One PointData of all scans (read_point_cloud's answer for .e57): the
// attributes every scan has, of one type, concatenated, plus "scan_index".
PointData merge_scans(std::vector<PointData>&& scans) {
  PointData m;
  size_t total = 0;
  for (const PointData& s : scans) total += s.num_points();
  io::resize_fresh(m.positions, total * 3);
  std::vector<uint32_t> scan_index;
  io::resize_fresh(scan_index, total);
  size_t at = 0;
  for (size_t s = 0; s < scans.size(); ++s) {
    std::copy(scans[s].positions.begin(), scans[s].positions.end(), m.positions.begin() + 3 * at);
    std::fill(scan_index.begin() + at, scan_index.begin() + at + scans[s].num_points(), static_cast<uint32_t>(s));
    at += scans[s].num_points();
  }
  std::string not_merged;
  if (!scans.empty()) {
    for (const PointAttribute& a : scans[0].attributes) {
      const bool everywhere = std::all_of(scans.begin(), scans.end(), [&](const PointData& s) {
        const PointAttribute* b = s.find(a.name);
        return b && b->components == a.components && b->values.index() == a.values.index();
      });
      if (!everywhere) {
        not_merged += (not_merged.empty() ? "" : ", ") + a.name;
        continue;
      }
      std::visit(
          [&](const auto& first) {
            using Vec = std::decay_t<decltype(first)>;
            Vec all;
            all.reserve(total * static_cast<size_t>(a.components));
            for (const PointData& s : scans) {
              const Vec& v = std::get<Vec>(s.find(a.name)->values);
              all.insert(all.end(), v.begin(), v.end());
            }
            m.set(a.name, a.components, std::move(all));
          },
          a.values);
    }
  }
  m.set("scan_index", 1, std::move(scan_index));
  std::string names;
  int64_t dropped = 0, nonfinite = 0;
  for (const PointData& s : scans) {
    names += (names.empty() ? "" : "\n") + std::get<std::string>(s.metadata.at("scan_name"));
    if (auto it = s.metadata.find("dropped_invalid"); it != s.metadata.end()) dropped += std::get<int64_t>(it->second);
    if (auto it = s.metadata.find("dropped_nonfinite"); it != s.metadata.end())
      nonfinite += std::get<int64_t>(it->second);
  }
  if (!scans.empty()) {
    for (const char* key : {"version", "coordinate_metadata", "images2d", "images2d_count"})
      m.metadata[key] = scans[0].metadata.at(key);
  }
  m.metadata["format"] = std::string("e57");
  m.metadata["point_count"] = static_cast<int64_t>(total);
  m.metadata["scan_count"] = static_cast<int64_t>(scans.size());
  m.metadata["scan_names"] = names;
  // Each scan's scanner position (its pose translation), 3 per scan: where
  // grid normals face (pointnpr.grid_normals).
  std::vector<double> origins;
  for (const PointData& s : scans) {
    const auto& t = std::get<std::vector<double>>(s.metadata.at("pose_translation"));
    origins.insert(origins.end(), t.begin(), t.end());
  }
  m.metadata["scan_origins"] = std::move(origins);
  if (dropped) m.metadata["dropped_invalid"] = dropped;
  if (nonfinite) m.metadata["dropped_nonfinite"] = nonfinite;
  if (!not_merged.empty()) m.metadata["attributes_not_in_every_scan"] = not_merged;
  return m;
}

}  // namespace

PointData read_e57_memory(const uint8_t* data, size_t size, const std::string& name, bool verify_checksums) {
  return merge_scans(read_e57_scans_memory(data, size, name, verify_checksums));
}

PointData read_e57(const std::string& path) { return merge_scans(read_e57_scans(path)); }

}  // namespace pointnpr
