#pragma once
// Conversions shared by the binding units.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <map>
#include <string>
#include <vector>

#include "core/params.h"

namespace pointnpr::python {

// Python dict {name: number | bool | str (enum item or path) | os.PathLike |
// sequence (color)} -> the arguments of validate(); unknown enum items raise
// ParameterError.
struct RawParams {
  std::map<std::string, std::vector<double>> numbers;
  std::map<std::string, std::string> paths;
};
RawParams to_raw_params(const Schema& schema, const pybind11::dict& values);
pybind11::dict schema_to_dict(const Schema& schema);
pybind11::dict values_to_dict(const ParamValues& values);

}  // namespace pointnpr::python
