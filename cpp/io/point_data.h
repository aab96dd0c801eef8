#pragma once
// In-memory result of reading a point cloud file: exact double positions,
// named per-point attributes of their natural type, and file metadata.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace pointnpr {

namespace io {
// Asks the kernel to back the whole 2 MB pages inside [p, p + bytes) with
// transparent huge pages (Linux; a no-op elsewhere or below 4 MB). Readers
// fill large fresh buffers once: 4 KB page faults are a large part of that
// cost (most of it on virtual machines), 2 MB ones are 512 times fewer.
void advise_huge_pages(const void* p, size_t bytes);

// Makes an empty vector hold n value-initialised elements, with huge pages
// advised before they are first touched.
template <class T>
void resize_fresh(std::vector<T>& v, size_t n) {
  if (n * sizeof(T) >= (size_t{4} << 20)) {
    std::vector<T> fresh;
    fresh.reserve(n);
    advise_huge_pages(fresh.data(), n * sizeof(T));
    v.swap(fresh);
  }
  v.assign(n, T{});
}
}  // namespace io

// One per-point attribute: `components` values per point, stored row-major
// (point i, component c at index i * components + c).
using AttributeValues =
    std::variant<std::vector<uint8_t>, std::vector<int8_t>, std::vector<uint16_t>,
                 std::vector<int16_t>, std::vector<uint32_t>, std::vector<int32_t>,
                 std::vector<uint64_t>, std::vector<int64_t>, std::vector<float>,
                 std::vector<double>>;

struct PointAttribute {
  std::string name;
  int components = 1;
  AttributeValues values;

  // Number of points covered (values / components).
  size_t num_points() const;
};

// Metadata values: text, integers, reals, or short lists of reals
// (scale, offset, bounds).
using MetadataValue = std::variant<std::string, int64_t, double, std::vector<double>>;

struct PointData {
  // N*3 georeferenced coordinates (LAS: raw integer * scale + offset).
  std::vector<double> positions;
  // Ordered by appearance; names are unique. Standard names:
  //   "colors" uint8 x3 (8-bit sRGB), "alpha" uint8, "intensity" float32,
  //   "classification" uint8, "return_number" uint8, "number_of_returns" uint8,
  //   "gps_time" float64, "nir" uint16, "scan_angle" float32 (degrees),
  //   "normals" float32 x3, plus format-specific extras.
  // A deque so that references returned by add() stay valid as more are added.
  std::deque<PointAttribute> attributes;
  // "format" ("las", "ply", "pcd", "text"), "version", "point_format",
  // "crs_wkt", "crs_epsg", "scale", "offset", ... (see docs/python_api.md).
  std::map<std::string, MetadataValue> metadata;

  size_t num_points() const { return positions.size() / 3; }
  const PointAttribute* find(const std::string& name) const;
  PointAttribute* find(const std::string& name);
  bool has(const std::string& name) const { return find(name) != nullptr; }

  // Typed access; nullptr when absent or of another type.
  template <class T>
  const std::vector<T>* get(const std::string& name) const {
    const PointAttribute* a = find(name);
    return a ? std::get_if<std::vector<T>>(&a->values) : nullptr;
  }

  // Adds (or replaces) an attribute; values.size() must be num_points() * components.
  template <class T>
  std::vector<T>& add(const std::string& name, int components = 1) {
    PointAttribute* a = find(name);
    if (!a) {
      attributes.push_back(PointAttribute{name, components, std::vector<T>{}});
      a = &attributes.back();
    }
    a->components = components;
    std::vector<T> values;
    io::resize_fresh(values, num_points() * static_cast<size_t>(components));
    a->values = std::move(values);
    return std::get<std::vector<T>>(a->values);
  }

  // Adds (or replaces) an attribute with the given values (moved, not
  // copied); values.size() must be num_points() * components.
  template <class T>
  void set(const std::string& name, int components, std::vector<T>&& values) {
    PointAttribute* a = find(name);
    if (!a) {
      attributes.push_back(PointAttribute{name, components, std::move(values)});
      return;
    }
    a->components = components;
    a->values = std::move(values);
  }

  void remove(const std::string& name);

  // Removes points whose position is not finite (NaN/inf); returns how many
  // were removed and records "dropped_nonfinite" in metadata if any.
  size_t drop_nonfinite_points();
};

}  // namespace pointnpr
