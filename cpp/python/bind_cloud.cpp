// PointCloud's constructor from numpy arrays (bound in bind_render.cpp).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/error.h"
#include "python/make_cloud.h"
#include "scene/point_cloud.h"

namespace py = pybind11;

namespace pointnpr::python {

template <class T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

std::shared_ptr<PointCloud> make_cloud(const py::object& positions, const py::object& colors,
                                       const py::object& intensity, const py::object& classification,
                                       const py::object& point_index, const py::object& normals,
                                       uint32_t chunk_size, const py::object& sensor, const py::object& opacity,
                                       const py::object& scales, const py::object& rotations, const py::object& sh,
                                       int sh_degree, bool antialiased) {
  // float32 positions (Blender's vertices) are read as they are; anything
  // else is converted to float64 (the exact georeferenced coordinates).
  CArray<double> pos;
  CArray<float> pos32;
  const py::array given = py::array::ensure(positions);
  const bool single = given && given.dtype().is(py::dtype::of<float>());
  if (single)
    pos32 = given.cast<CArray<float>>();
  else
    pos = positions.cast<CArray<double>>();
  const py::ssize_t ndim = single ? pos32.ndim() : pos.ndim();
  if (ndim != 2 || (single ? pos32.shape(1) : pos.shape(1)) != 3) throw Error("positions must be an (N,3) array");
  const size_t n = size_t(single ? pos32.shape(0) : pos.shape(0));
  PointCloudInput in;
  if (single)
    in.positions_f32 = {pos32.data(), n * 3};
  else
    in.positions = {pos.data(), n * 3};
  CArray<uint8_t> col;
  if (!colors.is_none()) {
    py::array any = py::array::ensure(colors);
    if (!any) throw Error("colors must be an array");
    if (any.dtype().kind() == 'f') {
      // Float colours are display sRGB in [0,1].
      auto f = py::module_::import("numpy").attr("clip")(any, 0.0, 1.0);
      any = py::array::ensure(py::module_::import("numpy").attr("rint")(f * py::float_(255.0)));
    }
    col = any.cast<CArray<uint8_t>>();
    if (col.ndim() != 2 || (col.shape(1) != 3 && col.shape(1) != 4) || size_t(col.shape(0)) != n)
      throw Error("colors must be an (N,3) or (N,4) array");
    in.colors = {col.data(), size_t(col.size())};
    in.color_channels = int(col.shape(1));
  }
  CArray<float> inten;
  if (!intensity.is_none()) {
    inten = intensity.cast<CArray<float>>();
    in.intensity = {inten.data(), size_t(inten.size())};
  }
  CArray<uint8_t> cls;
  if (!classification.is_none()) {
    cls = classification.cast<CArray<uint8_t>>();
    in.classification = {cls.data(), size_t(cls.size())};
  }
  CArray<uint32_t> idx;
  if (!point_index.is_none()) {
    idx = point_index.cast<CArray<uint32_t>>();
    in.point_index = {idx.data(), size_t(idx.size())};
  }
  CArray<float> nrm;
  if (!normals.is_none()) {
    nrm = normals.cast<CArray<float>>();
    in.normals = {nrm.data(), size_t(nrm.size())};
  }
  if (!sensor.is_none()) {
    const auto xyz = sensor.cast<std::vector<double>>();
    if (xyz.size() != 3) throw Error("sensor must be (x, y, z)");
    in.sensor = glm::dvec3(xyz[0], xyz[1], xyz[2]);
  }
  // 3D Gaussian splats (scene/gaussian_splats.h): all four or none.
  CArray<float> op, sc, rot, shc;
  const int splat_arrays = int(!opacity.is_none()) + int(!scales.is_none()) + int(!rotations.is_none()) + int(!sh.is_none());
  if (splat_arrays != 0 && splat_arrays != 4)
    throw ParameterError("Gaussian splats need opacity, scales, rotations and sh together (or none of them)");
  if (splat_arrays == 4) {
    op = opacity.cast<CArray<float>>();
    sc = scales.cast<CArray<float>>();
    rot = rotations.cast<CArray<float>>();
    shc = sh.cast<CArray<float>>();
    in.opacity = {op.data(), size_t(op.size())};
    in.scales = {sc.data(), size_t(sc.size())};
    in.rotations = {rot.data(), size_t(rot.size())};
    in.sh = {shc.data(), size_t(shc.size())};
    in.sh_degree = sh_degree;
    in.antialiased = antialiased;
  }
  py::gil_scoped_release release;
  return std::make_shared<PointCloud>(in, chunk_size);
}

}  // namespace pointnpr::python
