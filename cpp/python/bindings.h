#pragma once
// Each concern binds itself into the module in its own translation unit,
// mirroring the C++ folders (core, render, io).
#include <pybind11/pybind11.h>

namespace pointnpr::python {
void bind_core(pybind11::module_& m);
void bind_render(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_geometry(pybind11::module_& m);
}  // namespace pointnpr::python
