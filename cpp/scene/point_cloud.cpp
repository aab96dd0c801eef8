#include "scene/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/morton.h"
#include "geometry/analysis.h"
#include "scene/gaussian_splats.h"

namespace pointnpr {

namespace {
std::atomic<uint64_t> g_next_cloud_id{1};

// Point i of the input, float64 or float32, in double.
struct InputPositions {
  const double* d = nullptr;
  const float* f = nullptr;
  glm::dvec3 operator[](size_t i) const {
    if (d) return {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
    return {double(f[3 * i]), double(f[3 * i + 1]), double(f[3 * i + 2])};
  }
};

bool is_finite(const glm::dvec3& q) { return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z); }

// The finite points' indices sorted by (Morton code, index): a total order,
// so the layout is deterministic. Instead of a (code, index) pair per point
// (16 bytes) it holds one index (4 bytes): a counting sort on the code's top
// bits (stable, so indices stay in order within a bucket), then each bucket
// sorted on its own with codes recomputed, which is the same order.
std::vector<uint32_t> morton_order(const InputPositions& p, size_t n, size_t finite, const glm::dvec3& lo,
                                   double scale) {
  auto code = [&](size_t i) {
    const glm::dvec3 q = p[i];
    return morton_code(uint64_t((q.x - lo.x) * scale), uint64_t((q.y - lo.y) * scale),
                       uint64_t((q.z - lo.z) * scale));
  };
  // About 64 points per bucket, at most 2^20 buckets (4 MB of counts).
  int bits = 0;
  while (bits < 20 && (size_t(64) << (bits + 1)) <= finite) ++bits;
  const int shift = 63 - bits;
  std::vector<uint32_t> start((size_t(1) << bits) + 1, 0);
  for (size_t i = 0; i < n; ++i)
    if (is_finite(p[i])) ++start[(code(i) >> shift) + 1];
  for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<uint32_t> order(finite);
  {
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    for (size_t i = 0; i < n; ++i)
      if (is_finite(p[i])) order[next[code(i) >> shift]++] = uint32_t(i);
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, start.size() - 1), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<std::pair<uint64_t, uint32_t>> keyed;
    for (size_t b = r.begin(); b < r.end(); ++b) {
      const uint32_t first = start[b], count = start[b + 1] - first;
      if (count < 2) continue;
      keyed.resize(count);
      for (uint32_t k = 0; k < count; ++k) keyed[k] = {code(order[first + k]), order[first + k]};
      std::sort(keyed.begin(), keyed.end());
      for (uint32_t k = 0; k < count; ++k) order[first + k] = keyed[k].second;
    }
  });
  return order;
}
}  // namespace

PointChunk chunk_around(const glm::dvec3& lo, const glm::dvec3& hi) {
  PointChunk chunk;
  chunk.origin = (lo + hi) * 0.5;
  chunk.local_min = glm::vec3(lo - chunk.origin);
  chunk.local_max = glm::vec3(hi - chunk.origin);
  // Float rounding of the offsets can leave a point just outside the box.
  const glm::vec3 pad(1e-4f);
  chunk.local_min -= pad * glm::max(glm::vec3(1.0f), glm::abs(chunk.local_min));
  chunk.local_max += pad * glm::max(glm::vec3(1.0f), glm::abs(chunk.local_max));
  return chunk;
}

PointCloud::PointCloud(const PointCloudInput& in, uint32_t max_chunk_points)
    : id_(g_next_cloud_id++), sensor_(in.sensor) {
  if (sensor_ && !(std::isfinite(sensor_->x) && std::isfinite(sensor_->y) && std::isfinite(sensor_->z)))
    throw Error("the sensor position must be finite");
  if (!in.positions.empty() && !in.positions_f32.empty())
    throw Error("positions are given twice (float64 and float32): give one of them");
  const size_t coordinates = in.positions.empty() ? in.positions_f32.size() : in.positions.size();
  if (coordinates % 3 != 0) throw Error("positions must be an N x 3 array");
  size_t n = coordinates / 3;  // then the number of finite points
  if (n > std::numeric_limits<uint32_t>::max() / 2) throw Error("point cloud too large (more than 2^31 points)");
  if (in.color_channels != 3 && in.color_channels != 4) throw Error("colors must have 3 or 4 channels");
  if (!in.colors.empty() && in.colors.size() != n * size_t(in.color_channels))
    throw Error("colors must have one row per point (" + std::to_string(n) + ")");
  if (!in.intensity.empty() && in.intensity.size() != n) throw Error("intensity must have one value per point");
  if (!in.classification.empty() && in.classification.size() != n)
    throw Error("classification must have one value per point");
  if (!in.point_index.empty() && in.point_index.size() != n) throw Error("point_index must have one value per point");
  if (!in.normals.empty() && in.normals.size() != n * 3) throw Error("normals must be an N x 3 array");
  if (max_chunk_points == 0) throw Error("max_chunk_points must be positive");
  const bool splats = !in.opacity.empty() || !in.scales.empty() || !in.rotations.empty() || !in.sh.empty();
  const size_t coeffs = size_t(in.sh_degree + 1) * size_t(in.sh_degree + 1);
  if (splats) {
    if (in.sh_degree < 0 || in.sh_degree > 3) throw Error("sh_degree must be 0 to 3");
    if (in.opacity.size() != n) throw Error("Gaussian splats need one opacity per point");
    if (in.scales.size() != n * 3) throw Error("Gaussian splats need scales as an N x 3 array");
    if (in.rotations.size() != n * 4) throw Error("Gaussian splats need rotations as an N x 4 array (w, x, y, z)");
    if (in.sh.size() != n * 3 * coeffs)
      throw Error("Gaussian splats need sh as an N x " + std::to_string(3 * coeffs) + " array (degree " +
                  std::to_string(in.sh_degree) + ")");
  }

  const InputPositions p{in.positions.empty() ? nullptr : in.positions.data(),
                         in.positions.empty() ? in.positions_f32.data() : nullptr};
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  // Points with a non-finite coordinate are left out (counted; the host
  // says so once per object); the others keep their ids.
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 q = p[i];
    if (!is_finite(q)) {
      ++skipped_nonfinite_;
      continue;
    }
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  if (n == skipped_nonfinite_) lo = hi = glm::dvec3(0.0);
  bounds_min_ = lo;
  bounds_max_ = hi;

  // Morton order: points close in space are close in memory, so chunks are
  // compact boxes (good culling) and rasterization touches memory coherently.
  const glm::dvec3 extent = glm::max(hi - lo, glm::dvec3(1e-12));
  const double scale = double((1u << 21) - 1) / std::max({extent.x, extent.y, extent.z});
  const std::vector<uint32_t> order = morton_order(p, n, n - skipped_nonfinite_, lo, scale);
  n = order.size();

  local_positions_.resize(n);
  point_index_.resize(n);
  if (!in.colors.empty()) colors_.resize(n);
  if (!in.intensity.empty()) intensity_.resize(n);
  if (!in.classification.empty()) classification_.resize(n);
  if (!in.normals.empty()) normals_.resize(n);
  std::shared_ptr<GaussianSplats> g;
  if (splats) {
    g = std::make_shared<GaussianSplats>();
    g->sh_degree = in.sh_degree;
    g->antialiased = in.antialiased;
    g->opacity.resize(n);
    g->scales.resize(n);
    g->rotations.resize(n);
    g->sh.resize(n * 3 * coeffs);
  }

  for (size_t first = 0; first < n; first += max_chunk_points) {
    const size_t count = std::min<size_t>(max_chunk_points, n - first);
    glm::dvec3 clo(std::numeric_limits<double>::max()), chi(-std::numeric_limits<double>::max());
    for (size_t k = first; k < first + count; ++k) {
      const glm::dvec3 q = p[order[k]];
      clo = glm::min(clo, q);
      chi = glm::max(chi, q);
    }
    PointChunk chunk = chunk_around(clo, chi);
    chunk.first = uint32_t(first);
    chunk.count = uint32_t(count);
    for (size_t k = first; k < first + count; ++k) {
      const uint32_t i = order[k];
      local_positions_[k] = glm::vec3(p[i] - chunk.origin);
      point_index_[k] = in.point_index.empty() ? i : in.point_index[i];
      if (!in.colors.empty()) {
        const uint8_t* c = in.colors.data() + size_t(in.color_channels) * i;
        const uint32_t a = in.color_channels == 4 ? c[3] : 255u;
        colors_[k] = uint32_t(c[0]) | uint32_t(c[1]) << 8 | uint32_t(c[2]) << 16 | a << 24;
      }
      if (!in.intensity.empty()) intensity_[k] = in.intensity[i];
      if (!in.classification.empty()) classification_[k] = in.classification[i];
      if (!in.normals.empty())
        normals_[k] = glm::vec3(in.normals[3 * i], in.normals[3 * i + 1], in.normals[3 * i + 2]);
      if (g) {
        g->opacity[k] = in.opacity[i];
        g->scales[k] = glm::vec3(in.scales[3 * i], in.scales[3 * i + 1], in.scales[3 * i + 2]);
        g->rotations[k] = glm::vec4(in.rotations[4 * i], in.rotations[4 * i + 1], in.rotations[4 * i + 2],
                                    in.rotations[4 * i + 3]);
        std::copy_n(in.sh.data() + 3 * coeffs * i, 3 * coeffs, g->sh.data() + 3 * coeffs * k);
      }
    }
    chunks_.push_back(chunk);
  }
  gaussians_ = std::move(g);
}

PointCloud::PointCloud(PointCloudChunks&& in) : id_(g_next_cloud_id++) {
  const size_t n = in.local_positions.size();
  if (n > std::numeric_limits<uint32_t>::max() / 2) throw Error("point cloud too large (more than 2^31 points)");
  size_t next = 0;
  for (const PointChunk& c : in.chunks) {
    if (c.first != next || c.count > n - next) throw Error("chunks must tile the points in order");
    next += c.count;
  }
  if (next != n) throw Error("chunks must tile the points in order");
  if (in.point_index.size() != n) throw Error("point_index must have one value per point");
  for (size_t size : {in.colors.size(), in.intensity.size(), in.classification.size(), in.normals.size()})
    if (size != 0 && size != n) throw Error("chunked attributes must be empty or have one value per point");
  chunks_ = std::move(in.chunks);
  local_positions_ = std::move(in.local_positions);
  colors_ = std::move(in.colors);
  intensity_ = std::move(in.intensity);
  classification_ = std::move(in.classification);
  point_index_ = std::move(in.point_index);
  normals_ = std::move(in.normals);
  bounds_min_ = in.bounds_min;
  bounds_max_ = in.bounds_max;
}

bool PointCloud::has(Attribute a) const {
  switch (a) {
    case Attribute::Color: return !colors_.empty();
    case Attribute::Intensity: return !intensity_.empty();
    case Attribute::Classification: return !classification_.empty();
    case Attribute::Normal: return !normals_.empty();
  }
  return false;
}

std::vector<double> PointCloud::positions_double() const {
  std::vector<double> out(size() * 3);
  for (const auto& c : chunks_)
    for (uint32_t k = c.first; k < c.first + c.count; ++k) {
      const glm::dvec3 q = c.origin + glm::dvec3(local_positions_[k]);
      out[3 * k] = q.x;
      out[3 * k + 1] = q.y;
      out[3 * k + 2] = q.z;
    }
  return out;
}

geometry::Analysis& PointCloud::analysis() const {
  std::lock_guard lock(analysis_mutex_);
  if (!analysis_) analysis_ = std::make_shared<geometry::Analysis>(*this);
  return *analysis_;
}

}  // namespace pointnpr
