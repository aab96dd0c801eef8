// Python bindings of the out-of-core scan cache (io/scan_cache.h,
// scene/cached_cloud.h): pointnpr.write_scan_cache and pointnpr.CachedCloud,
// which Scene.add_segment takes in place of a PointCloud.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "io/readers.h"
#include "io/scan_cache.h"
#include "io/scan_cache_stream.h"
#include "python/bindings.h"
#include "render/streamed_cloud.h"
#include "scene/cached_cloud.h"

namespace py = pybind11;

namespace pointnpr::python {
namespace {

py::array_t<uint32_t> counts_array(const std::vector<uint32_t>& counts) {
  py::array_t<uint32_t> a(py::ssize_t(counts.size()));
  std::copy(counts.begin(), counts.end(), a.mutable_data());
  return a;
}

std::string path_bytes(const py::object& path) {
  return py::module_::import("os").attr("fsencode")(path).cast<std::string>();
}

}  // namespace

// The out-of-core cache (docs/io.md#scan-cache): written from a PointCloud,
// opened as a CachedCloud that Scene.add_segment takes in place of a cloud.
void bind_cache(py::module_& m) {
  m.attr("SCAN_CACHE_VERSION") = io::kScanCacheVersion;
  m.def(
      "write_scan_cache",
      [](py::object path, const PointCloud& cloud) {
        const std::string p = path_bytes(path);
        py::gil_scoped_release release;
        io::write_scan_cache(p, cloud);
      },
      py::arg("path"), py::arg("cloud"),
      "Writes a PointCloud as an out-of-core scan cache (its chunks, each in resolution-queue order, with "
      "checksums; docs/io.md#scan-cache). Raises pointnpr.Error when it cannot be written (no partial file).");

  m.def(
      "write_scan_caches",
      [](py::object scan, py::function path_for, std::optional<std::vector<double>> origin, bool split_by_classification,
         uint64_t memory_bytes, uint32_t chunk_size, const py::object& progress) {
        io::StreamedCacheOptions o;
        if (origin) {
          if (origin->size() != 3) throw ParameterError("origin must have 3 values");
          o.origin = {(*origin)[0], (*origin)[1], (*origin)[2]};
          for (int c = 0; c < 3; ++c)
            if (!std::isfinite(o.origin[c])) throw ParameterError("origin must be finite");
        } else {
          o.recentre = true;
        }
        o.split_by_classification = split_by_classification;
        o.memory_bytes = memory_bytes;
        o.max_chunk_points = chunk_size;
        const std::string p = path_bytes(scan);
        Progress* watch = progress.is_none() ? nullptr : progress.cast<Progress*>();
        std::vector<io::StreamedCache> written;
        {
          py::gil_scoped_release release;
          const ProgressScope scope(watch);
          written = io::write_scan_caches(
              [&](const ScanBlockSink& sink) { stream_las(p, sink); },
              [&](int classification) {
                py::gil_scoped_acquire gil;
                return path_bytes(path_for(classification));
              },
              o);
        }
        py::list out;
        for (const io::StreamedCache& c : written) {
          py::dict d;
          d["classification"] = c.classification;
          d["path"] = py::module_::import("os").attr("fsdecode")(py::bytes(c.path));
          d["points"] = c.points;
          d["rows"] = c.rows;
          d["runs"] = c.runs;
          d["refined_buckets"] = c.refined_buckets;
          d["origin"] = py::make_tuple(c.origin.x, c.origin.y, c.origin.z);
          out.append(d);
        }
        return out;
      },
      py::arg("scan"), py::arg("path_for"), py::arg("origin") = py::none(),
      py::arg("split_by_classification") = false, py::arg("memory_bytes") = uint64_t{256} << 20,
      py::arg("chunk_size") = 16384, py::arg("progress") = py::none(),
      "Writes out-of-core scan caches straight from a LAS or LAZ file, reading it a few times block by block, "
      "in about memory_bytes of memory whatever the scan's size (docs/io.md#scan-cache). The caches are the "
      "bytes write_scan_cache writes for PointCloud(float32(positions - origin), colors, intensity, "
      "classification) of the file (origin None: the centre of its bounds rounded to whole units, as the importer "
      "recentres) (one per class with split_by_classification, point ids the rows of the "
      "class). path_for(classification) names each cache (-1: not split). Returns a list of dicts "
      "(classification, path, points, rows, runs and refined_buckets: how the external sort went, origin). Raises ReadError for a bad file, pointnpr.Cancelled when progress "
      "is cancelled; a failure leaves no cache and no temporary file.");

  py::class_<CachedCloud, std::shared_ptr<CachedCloud>>(m, "CachedCloud",
      "A scan in an out-of-core cache, memory-mapped: each frame draws, within point_budget, a prefix of the "
      "resolution queue of every chunk in view, sized by its projected area. Use it in Scene.add_segment in "
      "place of a PointCloud.")
      .def(py::init([](py::object path, uint64_t budget) {
             const std::string p = path_bytes(path);
             py::gil_scoped_release release;
             return std::make_shared<CachedCloud>(p, budget);
           }),
           py::arg("path"), py::arg("point_budget") = kDefaultStreamBudget,
           "Opens and validates the cache; raises ReadError (missing, truncated, damaged, another version).")
      .def_property_readonly("path", [](const CachedCloud& c) { return c.cache().path(); })
      .def_property_readonly("num_points", [](const CachedCloud& c) { return c.cache().size(); })
      .def_property_readonly("num_chunks", [](const CachedCloud& c) { return c.cache().chunks().size(); })
      .def_property_readonly("file_bytes", [](const CachedCloud& c) { return c.cache().file_bytes(); })
      .def_property_readonly("bounds", [](const CachedCloud& c) {
        auto lo = c.cache().bounds_min(), hi = c.cache().bounds_max();
        return py::make_tuple(py::make_tuple(lo.x, lo.y, lo.z), py::make_tuple(hi.x, hi.y, hi.z));
      })
      .def("has", [](const CachedCloud& c, const std::string& name) {
        if (name == "colors") return c.cache().has(Attribute::Color);
        if (name == "intensity") return c.cache().has(Attribute::Intensity);
        if (name == "classification") return c.cache().has(Attribute::Classification);
        if (name == "normals") return c.cache().has(Attribute::Normal);
        throw ParameterError("unknown attribute '" + name + "' (colors, intensity, classification, normals)");
      })
      .def_property("point_budget", &CachedCloud::point_budget, &CachedCloud::set_point_budget,
                    "Points drawn per frame at most (all the chunks in view together).")
      .def_property_readonly("chunk_counts", [](const CachedCloud& c) {
        std::vector<uint32_t> n;
        for (const auto& ch : c.cache().chunks()) n.push_back(ch.count);
        return counts_array(n);
      })
      .def("counts_for_budget", [](const CachedCloud& c, uint64_t budget) {
        return counts_array(c.counts_for_budget(budget));
      }, py::arg("budget"), "Per chunk, the prefix drawn without a view: the same fraction of every chunk.")
      .def("counts_for_view", [](const CachedCloud& c, const Camera& cam, const py::object& matrix, int width,
                                 int height, std::optional<uint64_t> budget) {
        const glm::dmat4 world_from_object = to_dmat4(matrix, "world_from_object");
        const auto weights = chunk_view_weights(c.cache(), cam.view_from_world * world_from_object, cam,
                                                {width, height});
        return counts_array(c.counts_for(weights, budget.value_or(c.point_budget())));
      }, py::arg("camera"), py::arg("world_from_object"), py::arg("width"), py::arg("height"),
         py::arg("budget") = py::none(),
         "Per chunk, the prefix a render of this view draws (what Renderer.render streams).")
      .def("stream", [](const CachedCloud& c, py::array_t<uint32_t, py::array::c_style | py::array::forcecast> counts) {
        std::vector<uint32_t> n(counts.data(), counts.data() + counts.size());
        py::gil_scoped_release release;
        return std::const_pointer_cast<PointCloud>(c.stream(n));
      }, py::arg("counts"), "A PointCloud of the first counts[c] points of every chunk c (from the mapping).")
      .def("cloud", [](const CachedCloud& c, std::optional<uint64_t> budget) {
        py::gil_scoped_release release;
        return std::const_pointer_cast<PointCloud>(c.stream(c.counts_for_budget(budget.value_or(c.point_budget()))));
      }, py::arg("budget") = py::none(), "The cloud of a fixed budget: the same fraction of every chunk's queue.")
      .def("proxy", [](const CachedCloud& c, uint64_t points) {
        std::shared_ptr<const PointCloud> cloud;
        {
          py::gil_scoped_release release;
          cloud = c.stream(c.counts_for_budget(points));
        }
        const size_t n = cloud->size();
        py::array_t<float> pos({py::ssize_t(n), py::ssize_t(3)});
        float* w = pos.mutable_data();
        for (const PointChunk& ch : cloud->chunks())
          for (uint32_t i = ch.first; i < ch.first + ch.count; ++i) {
            const glm::dvec3 q = ch.origin + glm::dvec3(cloud->local_positions()[i]);
            w[3 * i] = float(q.x), w[3 * i + 1] = float(q.y), w[3 * i + 2] = float(q.z);
          }
        py::dict d;
        d["positions"] = pos;
        d["point_index"] = py::array_t<uint32_t>(py::ssize_t(n), cloud->point_index().data());
        if (cloud->has(Attribute::Color)) {
          py::array_t<uint8_t> col({py::ssize_t(n), py::ssize_t(3)});
          for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) col.mutable_data()[3 * i + k] = uint8_t(cloud->colors()[i] >> (8 * k));
          d["colors"] = col;
        }
        if (cloud->has(Attribute::Intensity))
          d["intensity"] = py::array_t<float>(py::ssize_t(n), cloud->intensity().data());
        if (cloud->has(Attribute::Classification)) {
          py::array_t<uint8_t> cls{py::ssize_t(n)};
          for (size_t i = 0; i < n; ++i) cls.mutable_data()[i] = uint8_t(cloud->classification()[i]);
          d["classification"] = cls;
        }
        return d;
      }, py::arg("points"),
         "A seeded subsample of about `points` points (the same share of every chunk's queue) as arrays: "
         "positions (float32, the cache's coordinates), point_index, and colors / intensity / classification "
         "where the cache has them: a light proxy of the scan for Blender's solid viewport.")
      .def_property_readonly("stream_bytes", &CachedCloud::stream_bytes,
                             "Heap bytes of the points streamed now (bounded by the budget, not the scan).")
      .def_property_readonly("stream_points", &CachedCloud::stream_points);
}


}  // namespace pointnpr::python
