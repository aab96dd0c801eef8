// Geometry analysis and segmentation (cpp/geometry/) as numpy functions.
// Every function takes a PointCloud (results in its internal order, that of
// cloud.point_index, computed once and cached on the cloud) or an (N,3)
// array of positions (results in the array's order, nothing cached).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <optional>

#include "core/error.h"
#include "core/progress.h"
#include "geometry/analysis.h"
#include "geometry/grid_normals.h"
#include "python/bindings.h"
#include "scene/point_cloud.h"

namespace py = pybind11;

namespace pointnpr::python {

namespace {

template <class T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

std::vector<uint32_t> pack_colors(const py::object& colors, size_t n) {
  if (colors.is_none()) return {};
  py::array any = py::array::ensure(colors);
  if (!any) throw Error("colors must be an array");
  if (any.dtype().kind() == 'f') {
    auto np = py::module_::import("numpy");
    any = py::array::ensure(np.attr("rint")(np.attr("clip")(any, 0.0, 1.0) * py::float_(255.0)));
  }
  CArray<uint8_t> c = any.cast<CArray<uint8_t>>();
  if (c.ndim() != 2 || (c.shape(1) != 3 && c.shape(1) != 4) || size_t(c.shape(0)) != n)
    throw Error("colors must be an (N,3) or (N,4) array with one row per point");
  std::vector<uint32_t> out(n);
  const int ch = int(c.shape(1));
  const uint8_t* p = c.data();
  for (size_t i = 0; i < n; ++i)
    out[i] = uint32_t(p[ch * i]) | uint32_t(p[ch * i + 1]) << 8 | uint32_t(p[ch * i + 2]) << 16 | 0xff000000u;
  return out;
}

std::vector<float> intensity_arg(const py::object& intensity, size_t n) {
  if (intensity.is_none()) return {};
  CArray<float> v = intensity.cast<CArray<float>>();
  if (v.ndim() != 1 || size_t(v.shape(0)) != n) throw Error("intensity must be an (N,) array with one value per point");
  return std::vector<float>(v.data(), v.data() + n);
}

// The analysis of a cloud (cached on it) or of a temporary point set.
struct Source {
  std::shared_ptr<PointCloud> cloud;
  std::unique_ptr<geometry::Analysis> temp;
  geometry::Analysis& get() { return cloud ? cloud->analysis() : *temp; }
  size_t size() { return get().size(); }
};

Source source(const py::object& points, const py::object& colors = py::none(),
              const py::object& intensity = py::none()) {
  Source s;
  if (py::isinstance<PointCloud>(points)) {
    s.cloud = points.cast<std::shared_ptr<PointCloud>>();
    if (!colors.is_none() || !intensity.is_none())
      throw Error("colours and intensity come from the PointCloud; pass positions to give others");
    return s;
  }
  CArray<double> pos = points.cast<CArray<double>>();
  if (pos.ndim() != 2 || pos.shape(1) != 3) throw Error("positions must be an (N,3) array or a PointCloud");
  const size_t n = size_t(pos.shape(0));
  std::vector<double> xyz(pos.data(), pos.data() + n * 3);
  s.temp = std::make_unique<geometry::Analysis>(std::move(xyz), pack_colors(colors, n), intensity_arg(intensity, n));
  return s;
}

template <class T>
py::array_t<T> array1(const std::vector<T>& v) {
  py::array_t<T> out(py::ssize_t(v.size()));
  if (!v.empty()) std::memcpy(out.mutable_data(), v.data(), v.size() * sizeof(T));
  return out;
}

py::array_t<float> array3(const std::vector<glm::vec3>& v) {
  py::array_t<float> out({py::ssize_t(v.size()), py::ssize_t(3)});
  if (!v.empty()) std::memcpy(out.mutable_data(), v.data(), v.size() * sizeof(glm::vec3));
  return out;
}

std::optional<glm::dvec3> vec3_arg(const py::object& o, const char* what) {
  if (o.is_none()) return std::nullopt;
  auto v = o.cast<std::vector<double>>();
  if (v.size() != 3) throw ParameterError(std::string(what) + " must be 3 numbers");
  for (double x : v)
    if (!std::isfinite(x)) throw ParameterError(std::string(what) + " must be finite");
  return glm::dvec3(v[0], v[1], v[2]);
}

// Runs a core call without the GIL, reporting to `progress` (a
// pointnpr.Progress or None) so that another Python thread can watch and
// cancel it.
template <class F>
auto without_gil(const py::object& progress, F&& call) {
  Progress* p = progress.is_none() ? nullptr : progress.cast<Progress*>();
  py::gil_scoped_release release;
  const ProgressScope scope(p);
  return call();
}

// Seed 001 eq. 2 over the masked points (none: all), with their chains.
geometry::LineFit masked_line_fit(const py::object& points, int k, const py::object& mask,
                                  const py::object& progress) {
  Source s = source(points);
  std::vector<uint8_t> msk;
  if (!mask.is_none()) {
    CArray<bool> b = mask.cast<CArray<bool>>();
    if (size_t(b.size()) != s.size()) throw Error("mask must have one value per point");
    msk.assign(b.data(), b.data() + b.size());
  }
  return without_gil(progress, [&] { return s.get().line_fit(msk, k); });
}

}  // namespace

void bind_geometry(py::module_& m) {
  py::class_<Progress>(m, "Progress",
                       "Progress and cancellation of a long geometry call: pass it as progress=, read fraction "
                       "from another thread, cancel() to make the call raise pointnpr.Cancelled at its next check.")
      .def(py::init<>())
      .def("cancel", &Progress::cancel, "Ask the call to stop; it raises pointnpr.Cancelled soon after.")
      .def_property_readonly("cancelled", &Progress::cancelled)
      .def_property_readonly("fraction", &Progress::fraction,
                             "Work done so far in [0, 1] (0 until the call has planned its work).");

  m.def(
      "estimate_normals",
      [](const py::object& points, int k, const py::object& orient_toward, const py::object& orient_direction,
         bool consistent, const py::object& progress) {
        Source s = source(points);
        geometry::NormalOptions o;
        o.k = k;
        const auto toward = vec3_arg(orient_toward, "orient_toward");
        const auto direction = vec3_arg(orient_direction, "orient_direction");
        if (toward && direction) throw ParameterError("give orient_toward or orient_direction, not both");
        if (toward) {
          o.orientation = geometry::Orientation::TowardPoint;
          o.target = *toward;
        } else if (direction) {
          o.orientation = geometry::Orientation::Direction;
          o.target = *direction;
        } else {
          o.orientation = consistent ? geometry::Orientation::Consistent : geometry::Orientation::None;
        }
        return array3(*without_gil(progress, [&] { return s.get().normals(o); }));
      },
      py::arg("points"), py::arg("k") = 16, py::arg("orient_toward") = py::none(),
      py::arg("orient_direction") = py::none(), py::arg("consistent") = true, py::arg("progress") = py::none(),
      "Unit normals (N,3) float32 by PCA of the k nearest neighbours (the point included), oriented "
      "toward a point (scanner/viewpoint), along a direction, else consistently (minimum spanning tree).");

  m.def(
      "grid_normals",
      [](CArray<double> positions, CArray<int64_t> rows, CArray<int64_t> columns, CArray<double> scanner) {
        if (positions.ndim() != 2 || positions.shape(1) != 3) throw py::value_error("positions must have shape (N, 3)");
        const size_t n = static_cast<size_t>(positions.shape(0));
        if (rows.ndim() != 1 || columns.ndim() != 1 || static_cast<size_t>(rows.shape(0)) != n ||
            static_cast<size_t>(columns.shape(0)) != n)
          throw py::value_error("rows and columns must have shape (N,), one per position");
        if (scanner.size() != 3) throw py::value_error("scanner must hold 3 coordinates");
        std::vector<float> normals;
        {
          py::gil_scoped_release release;
          normals = geometry::grid_normals(positions.data(), n, rows.data(), columns.data(), scanner.data());
        }
        py::array_t<float> out({static_cast<py::ssize_t>(n), py::ssize_t{3}});
        if (n) std::memcpy(out.mutable_data(), normals.data(), normals.size() * sizeof(float));
        return out;
      },
      py::arg("positions"), py::arg("rows"), py::arg("columns"), py::arg("scanner"),
      "Unit normals (N,3) float32 of a structured scan from its row/column grid (an E57 scan's row_index and "
      "column_index): per point the cross product of the differences to its nearer column and row neighbour, "
      "facing the scanner position (an E57 scan's pose translation); points without grid neighbours face the "
      "scanner. No neighbour search: much faster than estimate_normals, and oriented.");

  m.def(
      "curvature",
      [](const py::object& points, int k, const py::object& progress) {
        Source s = source(points);
        return array1(*without_gil(progress, [&] { return s.get().curvature(k); }));
      },
      py::arg("points"), py::arg("k") = 16, py::arg("progress") = py::none(),
      "Surface variation l0/(l0+l1+l2) in [0, 1/3], (N,) float32.");

  m.def(
      "local_resolution",
      [](const py::object& points, int k, const py::object& progress) {
        Source s = source(points);
        const auto r = without_gil(progress, [&] { return s.get().local_resolution(k); });
        return py::make_tuple(array1(r->r), array1(r->eps));
      },
      py::arg("points"), py::arg("k") = 8, py::arg("progress") = py::none(),
      "(r, eps): mean distance to the k nearest other points and its standard deviation, (N,) float32 each.");

  m.def(
      "feature_degree",
      [](const py::object& points, int k, const py::object& colors, const py::object& intensity, float color_weight,
         float contrast, const py::object& progress) {
        Source s = source(points, colors, intensity);
        const geometry::FeatureOptions o{color_weight, contrast};
        return array1(*without_gil(progress, [&] { return s.get().feature_degree(k, o); }));
      },
      py::arg("points"), py::arg("k") = 16, py::arg("colors") = py::none(), py::arg("intensity") = py::none(),
      py::arg("color_weight") = 0.5f, py::arg("contrast") = 25.0f, py::arg("progress") = py::none(),
      "Seed 001's feature degree in [0,1]: (1 - color_weight) x the variation of the normal-estimation error "
      "+ color_weight x colour/intensity edges (a point-space edge detector; CIELAB Delta E, saturating at "
      "contrast; intensity as a 0-100 lightness).");

  m.def(
      "line_fit",
      [](const py::object& points, int k, const py::object& mask, const py::object& progress) {
        const geometry::LineFit f = masked_line_fit(points, k, mask, progress);
        return py::make_tuple(array3(f.direction), array1(f.error));
      },
      py::arg("points"), py::arg("k") = 8, py::arg("mask") = py::none(), py::arg("progress") = py::none(),
      "(direction (N,3), error (N,)): least-squares line through the k nearest (masked) points (seed 001 eq. 2).");

  m.def(
      "feature_chains",
      [](const py::object& points, int k, const py::object& mask, const py::object& progress) {
        const geometry::LineFit f = masked_line_fit(points, k, mask, progress);
        return py::make_tuple(array3(f.to_parent), array1(f.chain_end));
      },
      py::arg("points"), py::arg("k") = 8, py::arg("mask") = py::none(), py::arg("progress") = py::none(),
      "(to_parent (N,3), ends (N,)): the (masked) points that lie along lines, linked into chains (a minimum "
      "spanning forest of links along their line fits, bridging gaps of up to 8 of the points' own "
      "spacings along a line, short side branches cut): the "
      "offset to each point's parent (0: none, or a chain's root) and its free ends (1: the point's, 2: its "
      "parent's), what the feature strokes mark draws an edge's line through.");

  m.def(
      "remove_outliers",
      [](const py::object& points, int k, float std_ratio, const py::object& progress) {
        Source s = source(points);
        const std::vector<uint8_t> keep = without_gil(progress, [&] { return s.get().inliers(k, std_ratio); });
        py::array_t<bool> out(py::ssize_t(keep.size()));
        for (size_t i = 0; i < keep.size(); ++i) out.mutable_data()[i] = keep[i] != 0;
        return out;
      },
      py::arg("points"), py::arg("k") = 20, py::arg("std_ratio") = 2.0f, py::arg("progress") = py::none(),
      "Statistical outlier removal: boolean (N,) mask of inliers (mean kNN distance <= mean + std_ratio*std).");

  m.def(
      "knn",
      [](const py::object& points, int k, const py::object& progress) {
        Source s = source(points);
        const auto nb = without_gil(progress, [&] { return s.get().knn(k); });
        const geometry::LocalPoints* lp = &s.get().points();
        const size_t n = lp->size();
        py::array_t<int64_t> idx({py::ssize_t(n), py::ssize_t(nb->k)});
        py::array_t<float> dist({py::ssize_t(n), py::ssize_t(nb->k)});
        for (size_t srt = 0; srt < n; ++srt) {
          const size_t row = lp->original[srt];
          for (int j = 0; j < nb->k; ++j) {
            idx.mutable_data()[row * nb->k + j] = lp->original[nb->at(srt)[j]];
            dist.mutable_data()[row * nb->k + j] = std::sqrt(nb->d2_at(srt)[j]);
          }
        }
        return py::make_tuple(idx, dist);
      },
      py::arg("points"), py::arg("k"), py::arg("progress") = py::none(),
      "(indices (N,k) int64, distances (N,k) float32): the k nearest points of each point, nearest first "
      "(the point itself or a duplicate first); k is clamped to N.");

  m.def(
      "radius_search",
      [](const py::object& points, const py::object& center, float radius) {
        Source s = source(points);
        const glm::dvec3 c = *vec3_arg(center, "center");
        std::vector<std::pair<uint32_t, float>> hits;
        const geometry::LocalPoints* lp = nullptr;
        {
          py::gil_scoped_release release;
          lp = &s.get().points();
          hits = s.get().tree().radius(glm::vec3(c - lp->origin), radius);
        }
        py::array_t<int64_t> idx(py::ssize_t(hits.size()));
        py::array_t<float> dist(py::ssize_t(hits.size()));
        for (size_t i = 0; i < hits.size(); ++i) {
          idx.mutable_data()[i] = lp->original[hits[i].first];
          dist.mutable_data()[i] = std::sqrt(hits[i].second);
        }
        return py::make_tuple(idx, dist);
      },
      py::arg("points"), py::arg("center"), py::arg("radius"),
      "(indices, distances) of the points within radius of center, nearest first.");

  m.def(
      "connected_components",
      [](const py::object& points, int level, uint32_t min_points, double cell_size, bool float32,
         const py::object& progress) {
        Source s = source(points);
        return array1(without_gil(progress, [&] {
                        return s.get().connected_components(level, min_points, cell_size, float32);
                      }).labels);
      },
      py::arg("points"), py::arg("level") = 8, py::arg("min_points") = 10, py::arg("cell_size") = 0.0,
      py::arg("float32") = false, py::arg("progress") = py::none(),
      "CloudCompare's Label Connected Components: int32 labels (N,), 0.. by decreasing size, -1 for "
      "components smaller than min_points. float32=True replays CloudCompare's float arithmetic.");

  m.def(
      "region_growing_rgb",
      [](const py::object& points, const py::object& colors, double distance_threshold, double point_color_threshold,
         double region_color_threshold, uint32_t min_cluster_size, uint32_t max_cluster_size, int k,
         int region_neighbours, const py::object& progress) {
        Source s = source(points, colors);
        geometry::RegionGrowingParams p;
        p.k = k;
        p.region_neighbours = region_neighbours;
        p.distance_threshold = distance_threshold;
        p.point_color_threshold = point_color_threshold;
        p.region_color_threshold = region_color_threshold;
        p.min_cluster_size = min_cluster_size;
        p.max_cluster_size = max_cluster_size;
        return array1(without_gil(progress, [&] { return s.get().region_growing_rgb(p); }).labels);
      },
      py::arg("points"), py::arg("colors") = py::none(), py::arg("distance_threshold") = 0.05,
      py::arg("point_color_threshold") = 6.0, py::arg("region_color_threshold") = 5.0,
      py::arg("min_cluster_size") = 10, py::arg("max_cluster_size") = 0xffffffffu, py::arg("k") = 30,
      py::arg("region_neighbours") = 0, py::arg("progress") = py::none(),
      "PCL RegionGrowingRGB: int32 labels (N,), 0.. by decreasing size, -1 outside the size limits. "
      "k: neighbours a region grows over; region_neighbours (0: k): neighbours and neighbouring segments "
      "searched for merging (PCL's defaults: 30 and 100).");

  m.def(
      "split_by_attribute",
      [](const py::object& values) {
        CArray<int64_t> v = values.cast<CArray<int64_t>>();
        if (v.ndim() != 1) throw Error("values must be a 1-D integer array");
        std::vector<geometry::Group> groups;
        {
          py::gil_scoped_release release;
          groups = geometry::split_by_attribute(std::span<const int64_t>(v.data(), size_t(v.size())));
        }
        py::dict out;
        for (const auto& g : groups) {
          py::array_t<int64_t> idx(py::ssize_t(g.indices.size()));
          for (size_t i = 0; i < g.indices.size(); ++i) idx.mutable_data()[i] = g.indices[i];
          out[py::int_(g.value)] = idx;
        }
        return out;
      },
      py::arg("values"), "{value: indices} for an integer attribute (LAS classification, labels), by value.");

  m.def(
      "computed_attributes",
      [](const PointCloud& cloud) { return cloud.analysis().computed(); }, py::arg("cloud"),
      "What the cloud's geometry cache holds so far (nothing until a geometry function asks).");
}

}  // namespace pointnpr::python
