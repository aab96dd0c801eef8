#pragma once
// PointCloud from numpy arrays: positions (N,3) float64 or float32, colours
// (N,3|4) uint8 or float sRGB, intensity, classification, point ids,
// normals, the sensor's position and, for 3D Gaussian splats, opacity (N,),
// scales (N,3), rotations (N,4) w x y z and sh (N, 3 (d+1)^2) of degree d,
// trained with anti-aliasing or not.
#include <cstdint>
#include <memory>

#include <pybind11/pybind11.h>

namespace pointnpr {
class PointCloud;
}

namespace pointnpr::python {
std::shared_ptr<PointCloud> make_cloud(const pybind11::object& positions, const pybind11::object& colors,
                                       const pybind11::object& intensity, const pybind11::object& classification,
                                       const pybind11::object& point_index, const pybind11::object& normals,
                                       uint32_t chunk_size, const pybind11::object& sensor,
                                       const pybind11::object& opacity, const pybind11::object& scales,
                                       const pybind11::object& rotations, const pybind11::object& sh, int sh_degree,
                                       bool antialiased);
}  // namespace pointnpr::python
