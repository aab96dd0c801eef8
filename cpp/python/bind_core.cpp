#include <pybind11/stl.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/image_io.h"
#include "gl/device.h"
#include "gl/shaders.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "render/filter.h"
#include "render/style.h"

namespace py = pybind11;

namespace pointnpr::python {

RawParams to_raw_params(const Schema& schema, const py::dict& values) {
  RawParams raw;
  const py::object fspath = py::module_::import("os").attr("fspath");
  for (auto [key, value] : values) {
    const std::string name = py::str(key);
    const ParamSpec* spec = schema.find(name);
    std::vector<double> v;
    if (spec && spec->type == ParamType::Path) {
      if (value.is_none()) {
        raw.paths[name] = "";
        continue;
      }
      if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__"))
        throw ParameterError(schema.id + "." + name + " expects a file path (str or os.PathLike)");
      raw.paths[name] = py::str(fspath(value));
      continue;
    }
    if (spec && spec->type == ParamType::Enum && py::isinstance<py::str>(value)) {
      // A former item may set another parameter too, unless that is given.
      std::map<std::string, std::vector<double>> set;
      set_enum_item(schema, *spec, py::str(value), set);
      for (auto& [param, number] : set) {
        if (param == spec->name)
          raw.numbers[name] = number;
        else
          raw.numbers.emplace(param, number);
      }
      continue;
    } else if (py::isinstance<py::str>(value)) {
      throw ParameterError(schema.id + "." + name + " expects a number, got a string");
    } else if (py::isinstance<py::sequence>(value)) {
      for (auto item : value.cast<py::sequence>()) v.push_back(item.cast<double>());
      // Colors may be given as RGB; alpha defaults to 1.
      if (spec && spec->type == ParamType::Color && v.size() == 3) v.push_back(1.0);
    } else {
      v.push_back(value.cast<double>());
    }
    raw.numbers[name] = std::move(v);
  }
  return raw;
}

namespace {
py::object param_value(const ParamSpec& spec, const std::vector<double>& v, const std::string& path = {}) {
  switch (spec.type) {
    case ParamType::Path: return py::str(path);
    case ParamType::Float: return py::float_(v[0]);
    case ParamType::Int: return py::int_(int(v[0]));
    case ParamType::Bool: return py::bool_(v[0] != 0.0);
    case ParamType::Enum: return py::str(spec.items.at(size_t(v[0])));
    case ParamType::Color: return py::make_tuple(v[0], v[1], v[2], v[3]);
  }
  return py::none();
}
// [{"param", "values"}, ...]: a "when"'s alternatives ("or") or
// requirements ("and").
py::list conditions_list(const std::vector<ParamSpec::Condition>& conditions) {
  py::list out;
  for (const ParamSpec::Condition& c : conditions) {
    py::dict condition;
    condition["param"] = c.param;
    condition["values"] = c.values;
    out.append(condition);
  }
  return out;
}
}  // namespace

py::dict schema_to_dict(const Schema& schema) {
  py::list params;
  for (const auto& p : schema.params) {
    py::dict d;
    d["name"] = p.name;
    d["type"] = to_string(p.type);
    d["default"] = param_value(p, p.default_value);
    d["min"] = p.min;
    d["max"] = p.max;
    d["unit"] = p.unit;
    d["doc"] = p.doc;
    d["items"] = p.items;
    d["former_names"] = p.former_names;
    d["older_files_value"] = p.older_files_value.empty() ? py::object(py::none()) : param_value(p, p.older_files_value);
    d["default_changed"] = p.default_changed;
    py::list former_items;
    for (const FormerItem& f : p.former_items) {
      py::dict item;
      item["name"] = f.name;
      item["now"] = f.now;
      item["also"] = f.also_param.empty() ? py::object(py::none()) : py::object(py::make_tuple(f.also_param, f.also_value));
      former_items.append(item);
    }
    d["former_items"] = former_items;
    d["older_files_items"] = p.older_files_items;
    if (p.when_param.empty()) {
      d["when"] = py::none();
    } else {
      py::dict when;
      when["param"] = p.when_param;
      when["values"] = p.when_values;
      if (!p.or_when.empty()) when["or"] = conditions_list(p.or_when);
      if (!p.and_when.empty()) when["and"] = conditions_list(p.and_when);
      d["when"] = when;
    }
    params.append(d);
  }
  py::dict out;
  out["id"] = schema.id;
  out["former_ids"] = schema.former_ids;
  out["label"] = schema.label;
  out["doc"] = schema.doc;
  out["kind"] = schema.kind;
  out["params"] = params;
  return out;
}

py::dict values_to_dict(const ParamValues& values) {
  py::dict out;
  for (const auto& p : values.schema().params)
    out[py::str(p.name)] = p.type == ParamType::Path ? py::str(values.get_path(p.name))
                                                     : param_value(p, values.raw().at(p.name));
  return out;
}

void bind_core(py::module_& m) {
  // Later registrations are tried first, so subclasses come after Error.
  auto& error = py::register_exception<Error>(m, "Error", PyExc_RuntimeError);
  py::register_exception<ParameterError>(m, "ParameterError", PyExc_ValueError);
  py::register_exception<GLError>(m, "GLError", error.ptr());
  py::register_exception<Cancelled>(m, "Cancelled", error.ptr());

  m.def("schemas", [] {
    py::list out;
    for (const MarkInfo* mark : registered_marks()) out.append(schema_to_dict(mark->schema));
    for (const FilterInfo* f : registered_filters()) out.append(schema_to_dict(f->schema));
    out.append(schema_to_dict(inpaint_schema()));
    out.append(schema_to_dict(composite_schema()));
    return out;
  }, "Parameter schemas of every mark, filter and pipeline stage (the single source of truth); "
     "each dict's 'kind' is 'mark', 'filter' or 'stage'.");

  m.def("set_shader_dir", &gl::set_shader_dir, "Folder the GLSL sources are read from.");
  m.def("shader_dir", &gl::shader_dir);
  m.def("gl_info", [] {
    const gl::DeviceInfo& info = gl::Device::instance().info();
    py::dict d;
    d["vendor"] = info.vendor;
    d["renderer"] = info.renderer;
    d["version"] = info.version;
    d["platform"] = info.egl_platform;
    d["software"] = info.software;
    d["int64_atomics"] = info.int64_atomics;
    d["max_texture_size"] = info.max_texture_size;
    return d;
  }, "Creates the headless GL context if needed and describes it.");
  m.def("shutdown", [] {
    py::gil_scoped_release release;
    gl::Device::shutdown();
  }, "Releases the GL context and its thread (it is re-created on next use).");

  m.def("save_image", [](const std::string& path, py::array_t<float, py::array::c_style | py::array::forcecast> pixels,
                         bool srgb) {
    if (pixels.ndim() != 2 && pixels.ndim() != 3) throw Error("save_image expects an (H,W) or (H,W,C) array");
    Image image;
    image.height = int(pixels.shape(0));
    image.width = int(pixels.shape(1));
    image.channels = pixels.ndim() == 3 ? int(pixels.shape(2)) : 1;
    image.pixels.assign(pixels.data(), pixels.data() + pixels.size());
    py::gil_scoped_release release;
    write_image(path, image, srgb);
  }, py::arg("path"), py::arg("pixels"), py::arg("srgb") = true,
     "Writes bottom-row-first float pixels through OpenImageIO (linear -> sRGB when srgb=True).");
  m.def("load_image", [](const std::string& path) {
    Image image = read_image(path);
    py::array_t<float> out({image.height, image.width, image.channels});
    std::copy(image.pixels.begin(), image.pixels.end(), out.mutable_data());
    return out;
  }, py::arg("path"), "Reads an image through OpenImageIO as (H,W,C) float32, bottom row first.");
}

}  // namespace pointnpr::python
