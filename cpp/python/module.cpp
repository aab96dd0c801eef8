#include "python/bindings.h"

namespace {

// pybind11 before 2.12 reads an array's item size from numpy 1's descriptor
// layout: under numpy 2 every array a binding makes repeats its first value
// (a curvature or feature degree the same for every point), silently. Such
// a build refuses numpy 2 rather than return wrong numbers.
void require_a_numpy_this_pybind11_reads() {
#if PYBIND11_VERSION_MAJOR < 2 || (PYBIND11_VERSION_MAJOR == 2 && PYBIND11_VERSION_MINOR < 12)
  const std::string version = pybind11::module_::import("numpy").attr("__version__").cast<std::string>();
  if (std::stoi(version) >= 2)  // the major version, the digits before the first dot
    throw pybind11::import_error("pointnpr: this module was built with pybind11 " PYBIND11_TOSTRING(
        PYBIND11_VERSION_MAJOR) "." PYBIND11_TOSTRING(PYBIND11_VERSION_MINOR) ", which misreads numpy " +
                                 version + "'s arrays; use numpy < 2, or a build with pybind11 2.12 or later "
                                           "(scripts/build.sh)");
#endif
}

}  // namespace

PYBIND11_MODULE(_pointnpr, m) {
  require_a_numpy_this_pybind11_reads();
  m.doc() = "PointNPR core: segment-based non-photorealistic rendering of point clouds";
  pointnpr::python::bind_core(m);
  pointnpr::python::bind_io(m);
  pointnpr::python::bind_render(m);
  pointnpr::python::bind_cache(m);
  pointnpr::python::bind_geometry(m);
}
