#pragma once
// Each concern binds itself into the module in its own translation unit,
// mirroring the C++ folders (core, render, io).
#include <pybind11/pybind11.h>

#include <glm/mat4x4.hpp>

namespace pointnpr::python {
void bind_core(pybind11::module_& m);
void bind_render(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_geometry(pybind11::module_& m);
void bind_cache(pybind11::module_& m);  // after bind_render: takes its PointCloud and Camera

// A 4x4 numpy-convertible matrix (row-major) as glm's; ParameterError names `what`.
glm::dmat4 to_dmat4(const pybind11::object& obj, const char* what);
}  // namespace pointnpr::python
