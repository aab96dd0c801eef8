// Python bindings of the point cloud readers and writers: pointnpr.read(path)
// -> PointData with numpy arrays, pointnpr.write(path, data), and
// pointnpr.ReadError (a ValueError).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "io/readers.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace pointnpr::python {
namespace {

// Python-side result: arrays are created once, at read time.
struct PyPointData {
  py::array positions;
  py::dict attributes;
  py::dict metadata;
  size_t num_points() const { return static_cast<size_t>(positions.shape(0)); }
};

// Moves a vector into a numpy array of shape (n,) or (n, comps) without copying.
template <class T>
py::array to_numpy(std::vector<T>&& v, size_t n, size_t comps) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(n)};
  if (comps != 1) shape.push_back(static_cast<py::ssize_t>(comps));
  if (v.empty()) return py::array_t<T>(shape);
  auto* heap = new std::vector<T>(std::move(v));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  std::vector<py::ssize_t> strides{static_cast<py::ssize_t>(comps * sizeof(T))};
  if (comps != 1) strides.push_back(static_cast<py::ssize_t>(sizeof(T)));
  return py::array_t<T>(shape, strides, heap->data(), owner);
}

// Text from files (names, software ids, WKT) need not be valid UTF-8.
py::str safe_str(const std::string& s) {
  PyObject* o = PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace");
  if (!o) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(o);
}

py::object metadata_value(const MetadataValue& v) {
  return std::visit(
      [](const auto& x) -> py::object {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::vector<double>>)
          return py::tuple(py::cast(x));
        else if constexpr (std::is_same_v<T, std::string>)
          return safe_str(x);
        else
          return py::cast(x);
      },
      v);
}

PyPointData convert(PointData&& d) {
  PyPointData out;
  const size_t n = d.num_points();
  for (PointAttribute& a : d.attributes) {
    const size_t comps = static_cast<size_t>(a.components);
    out.attributes[safe_str(a.name)] =
        std::visit([&](auto& v) { return to_numpy(std::move(v), n, comps); }, a.values);
  }
  for (const auto& [key, value] : d.metadata) out.metadata[safe_str(key)] = metadata_value(value);
  out.positions = to_numpy(std::move(d.positions), n, 3);
  return out;
}

// Copies a numpy array into a typed attribute vector (C order).
template <class T>
AttributeValues from_numpy(const py::array& a) {
  auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!c) throw py::error_already_set();
  return std::vector<T>(c.data(), c.data() + c.size());
}

// The C++ PointData of a Python one (copies; the writers read it in C++).
PointData to_cpp(const PyPointData& src) {
  PointData d;
  auto pos = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(src.positions);
  if (!pos || pos.ndim() != 2 || pos.shape(1) != 3)
    throw py::value_error("positions must be an (N, 3) array");
  d.positions.assign(pos.data(), pos.data() + pos.size());
  const auto n = pos.shape(0);
  for (auto item : src.attributes) {
    const std::string name = py::str(item.first).cast<std::string>();
    py::array a = py::array::ensure(item.second);
    if (!a || a.ndim() < 1 || a.ndim() > 2 || a.shape(0) != n)
      throw py::value_error("attribute '" + name +
                            "' must be an array of shape (N,) or (N, k) with N the point count");
    PointAttribute attr;
    attr.name = name;
    attr.components = a.ndim() == 2 ? static_cast<int>(a.shape(1)) : 1;
    if (attr.components < 1) throw py::value_error("attribute '" + name + "' has no columns");
    const py::dtype dt = a.dtype();
    const char kind = dt.kind();
    const auto size = dt.itemsize();
    if (kind == 'b' || (kind == 'u' && size == 1)) attr.values = from_numpy<uint8_t>(a);
    else if (kind == 'i' && size == 1) attr.values = from_numpy<int8_t>(a);
    else if (kind == 'u' && size == 2) attr.values = from_numpy<uint16_t>(a);
    else if (kind == 'i' && size == 2) attr.values = from_numpy<int16_t>(a);
    else if (kind == 'u' && size == 4) attr.values = from_numpy<uint32_t>(a);
    else if (kind == 'i' && size == 4) attr.values = from_numpy<int32_t>(a);
    else if (kind == 'u' && size == 8) attr.values = from_numpy<uint64_t>(a);
    else if (kind == 'i' && size == 8) attr.values = from_numpy<int64_t>(a);
    else if (kind == 'f' && size == 4) attr.values = from_numpy<float>(a);
    else if (kind == 'f' && size == 8) attr.values = from_numpy<double>(a);
    else
      throw py::value_error("attribute '" + name + "' has dtype " +
                            py::str(static_cast<py::object>(dt)).cast<std::string>() +
                            "; supported: bool, (u)int8-64, float32, float64");
    d.attributes.push_back(std::move(attr));
  }
  for (auto item : src.metadata) {
    const std::string key = py::str(item.first).cast<std::string>();
    py::handle v = item.second;
    if (py::isinstance<py::bool_>(v) || py::isinstance<py::int_>(v)) {
      try {
        d.metadata[key] = v.cast<int64_t>();
      } catch (const py::cast_error&) {
      }  // out of int64 range: not kept
    } else if (py::isinstance<py::float_>(v)) {
      d.metadata[key] = v.cast<double>();
    } else if (py::isinstance<py::str>(v)) {
      d.metadata[key] = v.cast<std::string>();
    } else if (py::isinstance<py::tuple>(v) || py::isinstance<py::list>(v)) {
      try {
        d.metadata[key] = v.cast<std::vector<double>>();
      } catch (const py::cast_error&) {
      }  // not a list of numbers: not kept
    }
  }
  return d;
}

PyObject* g_read_error = nullptr;  // leaked on purpose: lives as long as the process

bool is_exception_type(PyObject* t, PyObject* base) {
  return PyType_Check(t) && PyType_IsSubtype(reinterpret_cast<PyTypeObject*>(t),
                                             reinterpret_cast<PyTypeObject*>(base));
}

}  // namespace

void bind_io(py::module_& m) {
  // ReadError is a ValueError and, when the core has bound its common base
  // class (pointnpr.Error) before this, also one of those.
  py::tuple bases = py::make_tuple(py::handle(PyExc_ValueError));
  if (py::hasattr(m, "Error")) {
    py::object base = m.attr("Error");
    if (is_exception_type(base.ptr(), PyExc_Exception) &&
        !is_exception_type(base.ptr(), PyExc_ValueError))
      bases = py::make_tuple(base, py::handle(PyExc_ValueError));
  }
  g_read_error = PyErr_NewException("pointnpr._pointnpr.ReadError", bases.ptr(), nullptr);
  if (!g_read_error) throw py::error_already_set();
  py::setattr(g_read_error, "__doc__",
              py::str("A point cloud file could not be read. The message names the file, the "
                      "reason and, where it applies, the byte offset; the same are available "
                      "as .file, .reason and .byte_offset (-1 when not applicable)."));
  m.add_object("ReadError", py::handle(g_read_error));
  // Registered after bind_core's Error translator, so it is tried first.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ReadError& e) {
      py::object inst = py::handle(g_read_error)(safe_str(e.what()));
      inst.attr("file") = safe_str(e.file());
      inst.attr("reason") = safe_str(e.reason());
      inst.attr("byte_offset") = py::int_(e.byte_offset());
      PyErr_SetObject(g_read_error, inst.ptr());
    }
  });

  py::class_<PyPointData>(m, "PointData",
                          "Contents of a point cloud file: exact float64 positions, named "
                          "per-point attributes (numpy arrays) and file metadata.")
      .def(py::init([](py::array_t<double, py::array::c_style | py::array::forcecast> positions,
                       py::object attributes, py::object metadata) {
             if (positions.ndim() != 2 || positions.shape(1) != 3)
               throw py::value_error("positions must have shape (N, 3)");
             PyPointData d;
             d.positions = positions;
             const auto n = positions.shape(0);
             if (!attributes.is_none()) {
               for (auto item : py::dict(attributes)) {
                 py::array a = py::array::ensure(item.second);
                 if (!a || a.ndim() < 1 || a.shape(0) != n)
                   throw py::value_error("attribute '" + py::str(item.first).cast<std::string>() +
                                         "' must be an array with one row per point");
                 d.attributes[item.first] = a;
               }
             }
             if (!metadata.is_none()) d.metadata = py::dict(metadata);
             return d;
           }),
           py::arg("positions"), py::arg("attributes") = py::none(),
           py::arg("metadata") = py::none())
      .def_readonly("positions", &PyPointData::positions,
                    "(N, 3) float64 georeferenced coordinates")
      .def_readonly("attributes", &PyPointData::attributes,
                    "dict name -> numpy array with one row per point (\"colors\" (N,3) uint8, "
                    "\"intensity\" (N,) float32, \"classification\" (N,) uint8, "
                    "\"normals\" (N,3) float32, ...)")
      .def_readonly("metadata", &PyPointData::metadata,
                    "dict: \"format\", \"version\", \"point_format\", \"crs_wkt\", \"crs_epsg\", "
                    "\"scale\", \"offset\", ... (whatever the file provides)")
      .def_property_readonly("num_points", &PyPointData::num_points)
      .def("__len__", &PyPointData::num_points)
      .def(
          "to_cloud",
          [](py::object self) { return py::module_::import("pointnpr.io").attr("to_cloud")(self); },
          "PointCloud with the attributes the renderer uses (colors, intensity, classification)")
      .def("__repr__", [](const PyPointData& d) {
        std::string r = "<PointData ";
        r += d.metadata.contains("format") ? py::str(d.metadata["format"]).cast<std::string>()
                                           : std::string("?");
        r += ", ";
        r += std::to_string(d.num_points());
        r += " points, attributes: [";
        bool first = true;
        for (auto item : d.attributes) {
          if (!first) r += ", ";
          first = false;
          r += py::str(item.first).cast<std::string>();
        }
        r += "]>";
        return r;
      });

  m.def(
      "read",
      [](py::object path, py::object progress) {
        // Raw bytes of the path (os.fsencode), so that any file name the OS
        // accepts can be opened.
        const std::string p = py::module_::import("os").attr("fsencode")(path).cast<std::string>();
        Progress* watch = progress.is_none() ? nullptr : progress.cast<Progress*>();
        PointData data;
        {
          py::gil_scoped_release release;
          const ProgressScope scope(watch);
          data = read_point_cloud(p);
        }
        return convert(std::move(data));
      },
      py::arg("path"), py::arg("progress") = py::none(),
      "Reads a point cloud file (.las, .laz, .e57 (all scans merged), .ply (3DGS splats recognised), .spz, .pcd, "
      ".xyz/.pts/.txt/.csv) into a PointData. "
      "Raises ReadError (a ValueError) with the file, the reason and the byte offset. "
      "progress: a pointnpr.Progress that LAZ decoding reports to by chunk and stops on "
      "(raising Cancelled) once cancelled.");

  m.def(
      "read_e57_scans",
      [](py::object path, py::object progress) {
        const std::string p = py::module_::import("os").attr("fsencode")(path).cast<std::string>();
        Progress* watch = progress.is_none() ? nullptr : progress.cast<Progress*>();
        std::vector<PointData> scans;
        {
          py::gil_scoped_release release;
          const ProgressScope scope(watch);
          scans = read_e57_scans(p);
        }
        py::list out;
        for (PointData& s : scans) out.append(convert(std::move(s)));
        return out;
      },
      py::arg("path"), py::arg("progress") = py::none(),
      "Every scan of an .e57 file, one PointData each, in file order, with its pose applied "
      "(metadata scan_name, scan_guid, pose_rotation, pose_translation, coordinate_metadata, "
      "images2d, ...). read(path) gives the same points merged, with a scan_index attribute. progress: as read's. "
      "Raises ReadError (a ValueError) with the file, the reason and the byte offset.");

  m.def(
      "read_header",
      [](py::object path) {
        const std::string p = py::module_::import("os").attr("fsencode")(path).cast<std::string>();
        PointData data;
        {
          py::gil_scoped_release release;
          data = read_las_header(p);
        }
        return convert(std::move(data)).metadata;
      },
      py::arg("path"),
      "The metadata of a .las or .laz file (as read(path).metadata: point_count, bounds_min, bounds_max, scale, "
      "crs, ...) without reading its points. Raises ReadError for a bad header.");

  m.def(
      "write",
      [](py::object path, const PyPointData& data) {
        const std::string p = py::module_::import("os").attr("fsencode")(path).cast<std::string>();
        PointData d = to_cpp(data);
        py::gil_scoped_release release;
        write_point_cloud(p, d);
      },
      py::arg("path"), py::arg("data"),
      "Writes a PointData to .ply (binary little endian; attributes keep their type) or .las "
      "(LAS 1.4, point format 6/7/8; other attributes as extra bytes; crs_wkt / crs_epsg "
      "metadata kept; coordinates quantised to the source LAS grid when it holds them exactly, "
      "else to at most 0.1 mm). Raises pointnpr.Error when the data cannot be written.");
}

}  // namespace pointnpr::python
