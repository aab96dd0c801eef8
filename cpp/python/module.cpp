#include "python/bindings.h"

PYBIND11_MODULE(_pointnpr, m) {
  m.doc() = "PointNPR core: segment-based non-photorealistic rendering of point clouds";
  pointnpr::python::bind_core(m);
  pointnpr::python::bind_io(m);
  pointnpr::python::bind_render(m);
  pointnpr::python::bind_cache(m);
  pointnpr::python::bind_geometry(m);
}
