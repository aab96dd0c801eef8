#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>

#include "python/bindings.h"
#include "python/convert.h"
#include "python/make_cloud.h"
#include "marks/mesh_surface/mesh_surface.h"
#include "render/renderer.h"
#include "scene/cached_cloud.h"
#include "scene/gaussian_splats.h"

namespace py = pybind11;

namespace pointnpr::python {

template <class T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

glm::dmat4 to_dmat4(const py::object& obj, const char* what) {
  CArray<double> a = py::cast<CArray<double>>(py::module_::import("numpy").attr("asarray")(obj, "float64"));
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) throw ParameterError(std::string(what) + " must be a 4x4 matrix");
  glm::dmat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = a.at(r, c);  // numpy row-major -> glm column-major
  return m;
}

namespace {

// "vertex" or "corner" for an attribute of `rows` rows ("auto": by its count).
MeshDomain mesh_domain(const std::string& given, size_t rows, size_t vertices, size_t corners, const char* what) {
  if (given == "vertex") return MeshDomain::Vertex;
  if (given == "corner") return MeshDomain::Corner;
  if (given != "auto") throw ParameterError(std::string(what) + "_domain must be 'auto', 'vertex' or 'corner'");
  if (rows == vertices) return MeshDomain::Vertex;
  if (rows == corners) return MeshDomain::Corner;
  throw ParameterError(std::string("mesh ") + what + " must have one row per vertex (" + std::to_string(vertices) +
                       ") or per triangle corner (" + std::to_string(corners) + "), got " + std::to_string(rows));
}

// Float arrays in [0, 1] (display sRGB) become bytes.
CArray<uint8_t> color_bytes(const py::object& obj, const char* what) {
  py::array any = py::array::ensure(obj);
  if (!any) throw ParameterError(std::string(what) + " must be an array");
  if (any.dtype().kind() == 'f') {
    auto np = py::module_::import("numpy");
    any = py::array::ensure(np.attr("rint")(np.attr("clip")(np.attr("nan_to_num")(any), 0.0, 1.0) * py::float_(255.0)));
  }
  return any.cast<CArray<uint8_t>>();
}

std::shared_ptr<TriangleMesh> make_mesh(const py::object& positions, const py::object& triangles,
                                        const py::object& colors, const std::string& color_domain,
                                        const py::object& uvs, const std::string& uv_domain, const py::object& texture,
                                        const py::object& base_color) {
  CArray<double> pos = positions.cast<CArray<double>>();
  if (pos.ndim() != 2 || pos.shape(1) != 3) throw ParameterError("mesh positions must be a (V,3) array");
  py::array tri_any = py::array::ensure(triangles);
  if (!tri_any || tri_any.ndim() != 2 || tri_any.shape(1) != 3)
    throw ParameterError("mesh triangles must be a (T,3) array of vertex indices");
  if (tri_any.size() > 0) {
    auto np = py::module_::import("numpy");
    if (tri_any.dtype().kind() != 'i' && tri_any.dtype().kind() != 'u')
      throw ParameterError("mesh triangles must be integer vertex indices");
    if (np.attr("any")(tri_any.attr("__lt__")(0)).cast<bool>())
      throw ParameterError("mesh triangles must not hold negative indices");
  }
  CArray<uint32_t> tri = tri_any.cast<CArray<uint32_t>>();
  const size_t v = size_t(pos.shape(0)), corners = size_t(tri.size());
  TriangleMeshInput in;
  in.positions = {pos.data(), v * 3};
  in.indices = {tri.data(), corners};
  CArray<uint8_t> col;
  if (!colors.is_none()) {
    col = color_bytes(colors, "mesh colors");
    if (col.ndim() != 2 || (col.shape(1) != 3 && col.shape(1) != 4))
      throw ParameterError("mesh colors must be an (N,3) or (N,4) array");
    in.colors = {col.data(), size_t(col.size())};
    in.color_channels = int(col.shape(1));
    in.color_domain = mesh_domain(color_domain, size_t(col.shape(0)), v, corners, "colors");
  }
  CArray<float> uv;
  if (!uvs.is_none()) {
    uv = uvs.cast<CArray<float>>();
    if (uv.ndim() != 2 || uv.shape(1) != 2) throw ParameterError("mesh uvs must be an (N,2) array");
    in.uvs = {uv.data(), size_t(uv.size())};
    in.uv_domain = mesh_domain(uv_domain, size_t(uv.shape(0)), v, corners, "uvs");
  }
  CArray<uint8_t> tex;
  if (!texture.is_none()) {
    tex = color_bytes(texture, "mesh texture");
    if (tex.ndim() != 3 || tex.shape(2) != 4) throw ParameterError("mesh texture must be an (H,W,4) RGBA array");
    in.texture = {tex.data(), size_t(tex.size())};
    in.texture_size = {int(std::min<py::ssize_t>(tex.shape(1), 1 << 30)), int(std::min<py::ssize_t>(tex.shape(0), 1 << 30))};
  }
  if (!base_color.is_none()) {
    auto c = base_color.cast<std::vector<double>>();
    if (c.size() != 3 && c.size() != 4) throw ParameterError("mesh base_color must be RGB or RGBA");
    in.has_base_color = true;
    in.base_color = glm::vec4(float(c[0]), float(c[1]), float(c[2]), c.size() == 4 ? float(c[3]) : 1.0f);
  }
  py::gil_scoped_release release;
  return std::make_shared<TriangleMesh>(in);
}

ParamValues validated(const Schema& schema, const py::object& values) {
  if (values.is_none()) return validate(schema, {});
  const RawParams raw = to_raw_params(schema, values.cast<py::dict>());
  return validate(schema, raw.numbers, raw.paths);
}

std::string type_name(const py::handle& obj) {
  return std::string("'") + py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>() + "'";
}

// One entry of Scene.add_segment's instance list, checked with a message
// that says what was expected and what was given.
Instance instance_of(const py::object& item, const std::string& segment, size_t k) {
  const std::string where = "segment '" + segment + "', instance " + std::to_string(k) + ": ";
  const std::string expected =
      "expected a PointCloud, CachedCloud or TriangleMesh, or (one of them, 4x4 matrix[, object name])";
  Instance inst;
  if (py::isinstance<PointCloud>(item)) {
    inst.cloud = item.cast<std::shared_ptr<PointCloud>>();
    return inst;
  }
  if (py::isinstance<CachedCloud>(item)) {
    inst.cached = item.cast<std::shared_ptr<CachedCloud>>();
    return inst;
  }
  if (py::isinstance<TriangleMesh>(item)) {
    inst.mesh = item.cast<std::shared_ptr<TriangleMesh>>();
    return inst;
  }
  if (!py::isinstance<py::tuple>(item) && !py::isinstance<py::list>(item))
    throw ParameterError(where + expected + ", got " + type_name(item));
  auto t = item.cast<py::sequence>();
  if (t.size() != 2 && t.size() != 3)
    throw ParameterError(where + expected + ", got a sequence of " + std::to_string(t.size()) + " items");
  if (py::isinstance<TriangleMesh>(t[0]))
    inst.mesh = t[0].cast<std::shared_ptr<TriangleMesh>>();
  else if (py::isinstance<PointCloud>(t[0]))
    inst.cloud = t[0].cast<std::shared_ptr<PointCloud>>();
  else if (py::isinstance<CachedCloud>(t[0]))
    inst.cached = t[0].cast<std::shared_ptr<CachedCloud>>();
  else
    throw ParameterError(where + expected + ", got " + type_name(t[0]) + " where the cloud or mesh goes");
  try {
    inst.world_from_object = to_dmat4(t[1], "world_from_object");
  } catch (const py::error_already_set&) {
    throw ParameterError(where + "the matrix must be 4x4 numbers, got " + type_name(t[1]));
  } catch (const ParameterError& e) {
    throw ParameterError(where + e.what());
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(inst.world_from_object[c][r]))
        throw ParameterError(where + "the matrix has a non-finite entry");
  if (t.size() == 3) {
    if (!py::isinstance<py::str>(t[2])) throw ParameterError(where + "the object name must be a str, got " + type_name(t[2]));
    inst.name = t[2].cast<std::string>();
  }
  return inst;
}

// A plugin step given as 'id' or ('id', {params}).
std::pair<std::string, py::dict> step_of(const py::handle& item, const char* what) {
  py::object step = py::reinterpret_borrow<py::object>(item);
  if (py::isinstance<py::str>(step)) return {step.cast<std::string>(), py::dict()};
  auto t = step.cast<py::sequence>();
  if (t.size() != 2) throw ParameterError(std::string("a ") + what + " is 'id' or ('id', {params})");
  return {t[0].cast<std::string>(), t[1].is_none() ? py::dict() : t[1].cast<py::dict>()};
}

Style make_style(const py::object& mark, const py::object& filters, const py::object& inpaint,
                 const py::object& rasterize, const py::object& surface) {
  Style style;
  if (!mark.is_none() && !rasterize.is_none())
    throw ParameterError("give a style either mark= or rasterize= (the points mark's parameters), not both");
  if (!mark.is_none()) {
    const auto [id, params] = step_of(mark, "mark");
    const RawParams raw = to_raw_params(find_mark(id).schema, params);
    style.set_mark(id, raw.numbers, raw.paths);
  } else if (!rasterize.is_none()) {
    const RawParams raw = to_raw_params(find_mark("points").schema, rasterize.cast<py::dict>());
    style.set_mark("points", raw.numbers, raw.paths);
  }
  style.inpaint = validated(inpaint_schema(), inpaint);
  if (!surface.is_none()) {
    const RawParams raw = to_raw_params(find_mark("mesh_surface").schema, surface.cast<py::dict>());
    style.set_surface(raw.numbers);
  }
  if (!filters.is_none()) {
    for (auto item : filters.cast<py::sequence>()) {
      const auto [id, params] = step_of(item, "filter step");
      const RawParams raw = to_raw_params(find_filter(id).schema, params);
      style.add_filter(id, raw.numbers, raw.paths);
    }
  }
  return style;
}

py::list attribute_names(const AttributeSet& set) {
  py::list out;
  for (const AttributeKey& key : set) out.append(to_string(key));
  return out;
}

template <class T>
py::array_t<T> image_array(const std::vector<T>& data, int h, int w, int channels) {
  std::vector<py::ssize_t> shape = {h, w};
  if (channels > 1) shape.push_back(channels);
  py::array_t<T> out(shape);
  std::memcpy(out.mutable_data(), data.data(), data.size() * sizeof(T));
  return out;
}

// A read-only view into a result's buffer that keeps the result alive: the
// frame's pixels are not copied again on their way to numpy.
template <class T>
py::array_t<T> result_view(const std::vector<T>& data, int h, int w, int channels, py::handle owner) {
  std::vector<py::ssize_t> shape = {h, w};
  if (channels > 1) shape.push_back(channels);
  py::array_t<T> out(shape, data.data(), owner);
  py::detail::array_proxy(out.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return out;
}

}  // namespace

// render(native_limits={...}): the native backends' limits for one call
// (render/native_limits.h), for tests; an unknown key or a negative limit is an error.
NativeLimits native_limits_from(const py::dict& given) {
  NativeLimits limits;
  for (const auto& [key, value] : given) {
    const std::string name = py::str(key);
    if (name == "scalar_lanes") {
      limits.scalar_lanes = value.cast<bool>();
      continue;
    }
    uint64_t* field = name == "kept_frames_max" ? &limits.kept_frames_max
                      : name == "batch_splats"  ? &limits.batch_splats
                      : name == "max_bins"      ? &limits.max_bins
                                                : nullptr;
    if (!field)
      throw ParameterError("native_limits: unknown limit '" + name +
                           "' (scalar_lanes, kept_frames_max, batch_splats, max_bins)");
    const long long v = value.cast<long long>();
    if (v < 0) throw ParameterError("native_limits: " + name + " must be 0 (the backend's own) or a count");
    *field = uint64_t(v);
  }
  return limits;
}

void bind_render(py::module_& m) {
  py::register_exception<RenderCancelled>(m, "RenderCancelled", m.attr("Cancelled").ptr());

  py::class_<PointCloud, std::shared_ptr<PointCloud>>(m, "PointCloud",
      "Immutable point cloud split into chunks with double origins and float offsets.")
      .def(py::init(&make_cloud), py::arg("positions"), py::arg("colors") = py::none(),
           py::arg("intensity") = py::none(), py::arg("classification") = py::none(),
           py::arg("point_index") = py::none(), py::arg("normals") = py::none(), py::arg("chunk_size") = 16384,
           py::arg("sensor") = py::none(), py::arg("opacity") = py::none(), py::arg("scales") = py::none(),
           py::arg("rotations") = py::none(), py::arg("sh") = py::none(), py::arg("sh_degree") = 0,
           py::arg("antialiased") = false)
      .def_property_readonly("sh_degree", [](const PointCloud& c) -> py::object {
        if (!c.gaussians()) return py::none();
        return py::int_(c.gaussians()->sh_degree);
      }, "The SH degree of a cloud of 3D Gaussian splats, or None: plain points.")
      .def_property_readonly("num_points", &PointCloud::size)
      .def_property_readonly("sensor", [](const PointCloud& c) -> py::object {
        if (!c.sensor()) return py::none();
        return py::make_tuple(c.sensor()->x, c.sensor()->y, c.sensor()->z);
      }, "Where the sensor stood (a depth camera's frame), or None: estimated normals face it.")
      .def_property_readonly("skipped_points", &PointCloud::skipped_nonfinite,
                             "Input points left out for a non-finite coordinate (NaN or inf).")
      .def_property_readonly("num_chunks", [](const PointCloud& c) { return c.chunks().size(); })
      .def_property_readonly("id", &PointCloud::id)
      .def_property_readonly("bounds", [](const PointCloud& c) {
        auto lo = c.bounds_min(), hi = c.bounds_max();
        return py::make_tuple(py::make_tuple(lo.x, lo.y, lo.z), py::make_tuple(hi.x, hi.y, hi.z));
      })
      .def("has", [](const PointCloud& c, const std::string& name) {
        if (name == "colors") return c.has(Attribute::Color);
        if (name == "intensity") return c.has(Attribute::Intensity);
        if (name == "classification") return c.has(Attribute::Classification);
        if (name == "normals") return c.has(Attribute::Normal);
        throw ParameterError("unknown attribute '" + name + "' (colors, intensity, classification, normals)");
      })
      .def_property_readonly("point_index", [](const PointCloud& c) {
        return image_array(c.point_index(), 1, int(c.size()), 1).reshape({py::ssize_t(c.size())});
      }, "Stable point ids in the cloud's internal (Morton) order.");

  py::class_<TriangleMesh, std::shared_ptr<TriangleMesh>>(m, "TriangleMesh",
      "Immutable triangle mesh: a double origin with float vertex offsets, triangles, and optional colours "
      "(per vertex or corner), UVs with a base-colour image, and a base colour.")
      .def(py::init(&make_mesh), py::arg("positions"), py::arg("triangles"), py::arg("colors") = py::none(),
           py::arg("color_domain") = "auto", py::arg("uvs") = py::none(), py::arg("uv_domain") = "auto",
           py::arg("texture") = py::none(), py::arg("base_color") = py::none(),
           "positions (V,3) float64; triangles (T,3) vertex indices; colors (V or 3T, 3 or 4) display sRGB "
           "(uint8 or float in [0,1]); uvs (V or 3T, 2); texture (H,W,4) display sRGB, bottom row first; "
           "base_color (r, g, b[, a]) display sRGB. *_domain: 'auto' (by the row count), 'vertex' or 'corner'.")
      .def_property_readonly("num_vertices", &TriangleMesh::num_vertices)
      .def_property_readonly("num_triangles", &TriangleMesh::num_triangles)
      .def_property_readonly("id", &TriangleMesh::id)
      .def("sample_surface", [](const TriangleMesh& mesh, double density) {
        std::shared_ptr<const PointCloud> c;
        {
          py::gil_scoped_release release;
          c = mesh.sampled_cloud(density);
        }
        return std::const_pointer_cast<PointCloud>(c);
      }, py::arg("density"),
         "The points the 'sampled' mesh mode draws: density per square scene unit, seeded by triangle index.");

  py::class_<Style>(m, "Style", "A segment's pipeline: one mark -> filters -> depth inpainting.")
      .def(py::init(&make_style), py::arg("mark") = py::none(), py::arg("filters") = py::none(),
           py::arg("inpaint") = py::none(), py::arg("rasterize") = py::none(), py::arg("surface") = py::none(),
           "mark: 'id' or ('id', {params}) of a mark (default 'points'); filters: ['id' or ('id', {params})]; "
           "rasterize: the points mark's parameters (the older spelling of mark=('points', {...})); "
           "surface: the mesh_surface mark's parameters (how objects with faces are drawn).")
      .def_property_readonly("surface", [](const Style& s) { return values_to_dict(s.surface.params); },
                             "The mesh_surface mark's parameters.")
      .def_property_readonly("mesh_source_attributes", [](const Style& s) {
        // What a host reads from a mesh for this style: only the colour
        // sources the surface (or, for meshes drawn as points, the point
        // mark) uses.
        std::vector<std::string> out;
        const MeshMode mode = mesh_mode(s.surface.params);
        const auto point_sources = s.source_attributes();
        const bool point_colors = std::find(point_sources.begin(), point_sources.end(), "colors") != point_sources.end();
        if (mode == MeshMode::Surface) {
          const std::set<MeshAttribute> a = mesh_attributes(s.surface.params);
          if (s.surface.params.get_enum_name("color_source") != "constant") out.push_back("base_color");
          if (a.count(MeshAttribute::Color)) out.push_back("colors");
          if (a.count(MeshAttribute::Texture)) out.insert(out.end(), {"texture", "uvs"});
        } else if (mode == MeshMode::Sampled && point_colors) {
          out = {"base_color", "colors", "texture", "uvs"};
        } else if (point_colors) {
          out = {"colors"};
        }
        return out;
      }, "Mesh attributes a host passes to TriangleMesh for this style (base_color, colors, texture, uvs).")
      .def_property_readonly("mark", [](const Style& s) {
        return py::make_tuple(s.mark.info->schema.id, values_to_dict(s.mark.params));
      })
      .def_property_readonly("rasterize", [](const Style& s) -> py::object {
        if (s.mark.info->schema.id != "points") return py::none();
        return values_to_dict(s.mark.params);
      }, "The points mark's parameters, or None for another mark.")
      .def_property_readonly("attributes", [](const Style& s) { return attribute_names(s.attributes()); },
                             "Per-point attributes the mark reads ('normals:16', 'colors', ...).")
      .def_property_readonly("source_attributes", &Style::source_attributes,
                             "Attributes a host passes to PointCloud for this style (the core computes the rest); "
                             "for color_source 'auto' every colour attribute the object has.")
      .def_property_readonly("inpaint", [](const Style& s) { return values_to_dict(s.inpaint); })
      .def_property_readonly("filters", [](const Style& s) {
        py::list out;
        for (const auto& f : s.filters) out.append(py::make_tuple(f.info->schema.id, values_to_dict(f.params)));
        return out;
      });

  py::class_<Scene>(m, "Scene", "Segments in layering order (later segments on top).")
      .def(py::init<>())
      .def("add_segment", [](Scene& scene, const std::string& name, const Style& style, const py::object& instances) {
        Segment seg;
        seg.name = name;
        seg.style = style;
        if (py::isinstance<py::str>(instances) || !py::isinstance<py::sequence>(instances))
          throw ParameterError("segment '" + name + "': instances must be a list of PointCloud or TriangleMesh, or "
                               "(PointCloud, 4x4 matrix[, name]), got " + type_name(instances));
        size_t k = 0;
        for (auto item : instances.cast<py::sequence>()) {
          seg.instances.push_back(instance_of(py::reinterpret_borrow<py::object>(item), name, k++));
        }
        scene.segments.push_back(std::move(seg));
        return scene.segments.size() - 1;
      }, py::arg("name"), py::arg("style"), py::arg("instances"),
         "instances: [cloud or (cloud, world_from_object 4x4) or (cloud, matrix, object name)]; the name is used in "
         "render warnings.")
      .def_property_readonly("num_segments", [](const Scene& s) { return s.segments.size(); });

  py::class_<Camera>(m, "Camera", "Camera composed in double precision (Blender's camera model).")
      .def_static("perspective", [](const py::object& world_from_camera, double lens, double sensor_width,
                                    double sensor_height, const std::string& fit, double shift_x, double shift_y,
                                    double clip_start, double clip_end, int width, int height, double pixel_aspect) {
        return Camera::perspective(to_dmat4(world_from_camera, "world_from_camera"), lens, sensor_width,
                                   sensor_height, parse_sensor_fit(fit), shift_x, shift_y, clip_start, clip_end,
                                   {width, height}, pixel_aspect);
      }, py::arg("world_from_camera"), py::arg("lens") = 50.0, py::arg("sensor_width") = 36.0,
         py::arg("sensor_height") = 24.0, py::arg("sensor_fit") = "AUTO", py::arg("shift_x") = 0.0,
         py::arg("shift_y") = 0.0, py::arg("clip_start") = 0.1, py::arg("clip_end") = 1000.0, py::kw_only(),
         py::arg("width"), py::arg("height"), py::arg("pixel_aspect") = 1.0,
         "Blender's perspective camera. width/height are the render size in pixels (they decide the sensor fit "
         "and aspect); pixel_aspect = pixel height / pixel width (Blender: pixel_aspect_y / pixel_aspect_x).")
      .def_static("orthographic", [](const py::object& world_from_camera, double ortho_scale, const std::string& fit,
                                     double shift_x, double shift_y, double clip_start, double clip_end, int width,
                                     int height, double pixel_aspect) {
        return Camera::orthographic_camera(to_dmat4(world_from_camera, "world_from_camera"), ortho_scale,
                                           parse_sensor_fit(fit), shift_x, shift_y, clip_start, clip_end,
                                           {width, height}, pixel_aspect);
      }, py::arg("world_from_camera"), py::arg("ortho_scale") = 10.0, py::arg("sensor_fit") = "AUTO",
         py::arg("shift_x") = 0.0, py::arg("shift_y") = 0.0, py::arg("clip_start") = 0.1,
         py::arg("clip_end") = 1000.0, py::kw_only(), py::arg("width"), py::arg("height"),
         py::arg("pixel_aspect") = 1.0, "Blender's orthographic camera; width/height/pixel_aspect as for perspective().")
      .def_static("from_matrices", [](const py::object& view, const py::object& projection) {
        return Camera::from_matrices(to_dmat4(view, "view_matrix"), to_dmat4(projection, "projection_matrix"));
      }, py::arg("view_matrix"), py::arg("projection_matrix"))
      .def_readonly("orthographic_projection", &Camera::orthographic)
      .def_readonly("clip_start", &Camera::clip_start)
      .def_readonly("clip_end", &Camera::clip_end);

  py::class_<RenderResult>(m, "RenderResult")
      .def_property_readonly("color", [](py::object self) {
        const auto& r = self.cast<const RenderResult&>();
        return result_view(r.color, r.height, r.width, 4, self);
      }, "(H,W,4) float32 scene-linear premultiplied RGBA, bottom row first (read-only view)")
      .def_property_readonly("depth", [](py::object self) {
        const auto& r = self.cast<const RenderResult&>();
        return result_view(r.depth, r.height, r.width, 1, self);
      }, "(H,W) float32 linear view depth, 1e10 = background (read-only view)")
      .def_property_readonly("segment_index", [](py::object self) {
        const auto& r = self.cast<const RenderResult&>();
        return result_view(r.segment_index, r.height, r.width, 1, self);
      }, "(H,W) int32 front segment, -1 = background (read-only view)")
      .def_property_readonly("marks", [](const RenderResult& r) {
        const py::ssize_t n = py::ssize_t(r.marks.size());
        py::array_t<uint32_t> id(n);
        py::array_t<float> center({n, py::ssize_t(3)}), direction({n, py::ssize_t(3)}), normal({n, py::ssize_t(3)});
        py::array_t<float> length(n), color({n, py::ssize_t(4)});
        py::array_t<bool> crossed(n);
        py::array_t<uint32_t> kind(n);
        for (py::ssize_t i = 0; i < n; ++i) {
          const CapturedMark& mk = r.marks[size_t(i)];
          id.mutable_at(i) = mk.point_id;
          crossed.mutable_at(i) = mk.crossed;
          kind.mutable_at(i) = mk.kind;
          length.mutable_at(i) = mk.length;
          for (int c = 0; c < 3; ++c) {
            center.mutable_at(i, c) = mk.center[c];
            direction.mutable_at(i, c) = mk.direction[c];
            normal.mutable_at(i, c) = mk.normal[c];
          }
          for (int c = 0; c < 4; ++c) color.mutable_at(i, c) = mk.color[c];
        }
        py::dict d;
        d["point_id"] = id;
        d["center"] = center;
        d["direction"] = direction;
        d["normal"] = normal;
        d["crossed"] = crossed;
        d["length"] = length;
        d["color"] = color;
        d["kind"] = kind;
        return d;
      }, "Marks drawn (render(..., capture_marks=True)), view space: point_id, center, direction, normal, "
         "crossed, length (scene units), color (display sRGB, alpha = opacity), kind (the mark's class of point).")
      .def_readonly("stats", &RenderResult::stats)
      .def_readonly("warnings", &RenderResult::warnings)
      .def_readonly("width", &RenderResult::width)
      .def_readonly("height", &RenderResult::height);

  py::class_<Renderer>(m, "Renderer", "Renders scenes with the core's headless GL context; keeps point data on "
                                      "the GPU between frames.")
      .def(py::init([] {
        py::gil_scoped_release release;
        return std::make_unique<Renderer>();
      }))
      .def("render", [](Renderer& self, const Scene& scene, const Camera& camera, int width, int height, double time,
                        const py::object& composite, const py::object& background, const py::object& progress,
                        bool capture_marks, double memory_budget_gb, int tile_size, long long point_budget,
                        const py::dict& native_limits, bool int64_atomics, bool stage_timings) {
        RenderSettings s;
        s.stage_timings = stage_timings;
        s.native = native_limits_from(native_limits);
        s.int64_atomics = int64_atomics;
        if (point_budget < 0)
          throw ParameterError("point_budget must be 0 (every point) or a number of points, got " +
                               std::to_string(point_budget));
        s.point_budget = uint64_t(point_budget);
        if (!std::isfinite(memory_budget_gb) || memory_budget_gb < 0.0 || memory_budget_gb > 1e6)
          throw ParameterError("memory_budget_gb must be a positive number of GB (0 = the default, 2), got " +
                               std::to_string(memory_budget_gb));
        s.memory_budget = size_t(memory_budget_gb * double(size_t(1) << 30));
        if (tile_size < 0) throw ParameterError("tile_size must be 0 (from the memory budget) or a number of pixels");
        s.tile_size = tile_size;
        s.width = width;
        s.height = height;
        s.time = time;
        if (!std::isfinite(time)) throw ParameterError("time must be finite");
        s.composite = validated(composite_schema(), composite);
        auto bg = background.cast<std::vector<double>>();
        if (bg.size() != 4) throw ParameterError("background must be RGBA (4 values)");
        s.background = {bg[0], bg[1], bg[2], bg[3]};
        s.capture_marks = capture_marks;
        if (!progress.is_none()) {
          // Borrowed: `progress` outlives this call. Called with the GIL held.
          PyObject* fn = progress.ptr();
          s.progress = [fn](double f, const std::string& what) {
            py::gil_scoped_acquire gil;
            py::object r = py::reinterpret_borrow<py::object>(fn)(f, what);
            return r.is_none() || r.cast<bool>();
          };
        }
        py::gil_scoped_release release;
        return self.render(scene, camera, s);
      }, py::arg("scene"), py::arg("camera"), py::arg("width"), py::arg("height"), py::arg("time") = 0.0,
         py::arg("composite") = py::none(), py::arg("background") = std::vector<double>{0, 0, 0, 0},
         py::arg("progress") = py::none(), py::arg("capture_marks") = false, py::arg("memory_budget_gb") = 0.0,
         py::arg("tile_size") = 0, py::arg("point_budget") = 0, py::arg("native_limits") = py::dict(),
         py::arg("int64_atomics") = true, py::arg("stage_timings") = false)
      .def("cached_clouds", &Renderer::cached_clouds, py::call_guard<py::gil_scoped_release>())
      .def("uploaded_attributes", [](const Renderer& r, const PointCloud& c) {
        return attribute_names(r.uploaded_attributes(c.id()));
      }, "Attributes of the cloud on the GPU besides positions ('colors', 'normals:16', ...).")
      .def("upload_count", &Renderer::upload_count, py::call_guard<py::gil_scoped_release>())
      .def("cached_meshes", &Renderer::cached_meshes, py::call_guard<py::gil_scoped_release>())
      .def("mesh_upload_count", &Renderer::mesh_upload_count, py::call_guard<py::gil_scoped_release>(),
           "Mesh buffers and textures uploaded since the renderer was made.");
}

}  // namespace pointnpr::python
