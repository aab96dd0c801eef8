#pragma once
// A point cloud as the renderer sees it: spatially coherent chunks, each with
// a double-precision origin and float offsets, so precision never depends on
// where the cloud sits in the world (georeferenced scans at 1e6 m included).
#include <atomic>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

namespace pointnpr {

namespace geometry {
class Analysis;
}
struct GaussianSplats;  // scene/gaussian_splats.h

// Attributes a style can ask for; each is uploaded to the GPU only when some
// style rendering the cloud needs it.
enum class Attribute : uint32_t { Color = 1, Intensity = 2, Classification = 4, Normal = 8 };

struct PointChunk {
  glm::dvec3 origin;     // world offset of this chunk (object space of the cloud)
  uint32_t first = 0;    // range into the cloud's (reordered) arrays
  uint32_t count = 0;
  glm::vec3 local_min;   // bounds of the float offsets
  glm::vec3 local_max;
};

// The chunk box of points within [lo, hi]: its origin the centre, float
// bounds padded for the rounding of the offsets (first and count unset).
PointChunk chunk_around(const glm::dvec3& lo, const glm::dvec3& hi);

struct PointCloudInput {
  std::span<const double> positions;         // N*3
  // Or N*3 float32 (Blender's vertices, which are float32 already): read
  // point by point in double, so no float64 copy of the whole array is
  // made. At most one of positions and positions_f32 is non-empty.
  std::span<const float> positions_f32;
  std::span<const uint8_t> colors;            // N*channels, sRGB, or empty
  int color_channels = 3;                     // 3 (RGB) or 4 (RGBA)
  std::span<const float> intensity;           // N or empty
  std::span<const uint8_t> classification;    // N or empty
  std::span<const uint32_t> point_index;      // N or empty (then 0..N-1)
  std::span<const float> normals;             // N*3 or empty
  // Where the sensor stood, in the positions' frame, where the scan knows
  // it (a depth camera's frame: PCD's VIEWPOINT): estimated normals face it.
  std::optional<glm::dvec3> sensor;
  // 3D Gaussian splats (scene/gaussian_splats.h; all empty: plain points):
  // opacity N in [0, 1], scales N*3 (standard deviations, scene units),
  // rotations N*4 (unit quaternions w, x, y, z), sh N*3*(sh_degree+1)^2
  // (coefficient-major, r g b inner; DC first, display-referred sRGB).
  std::span<const float> opacity;
  std::span<const float> scales;
  std::span<const float> rotations;
  std::span<const float> sh;
  int sh_degree = 0;
  // Trained with anti-aliasing (Mip-Splatting, SPZ's flag 0x1): the
  // renderer scales a splat's opacity by the 2D filter's compensation.
  bool antialiased = false;
};

// Points already laid out in chunks (an out-of-core cache's prefixes,
// scene/cached_cloud.h): arrays chunk after chunk, attributes empty or one
// value per point, `bounds` those of the whole scan.
struct PointCloudChunks {
  std::vector<PointChunk> chunks;
  std::vector<glm::vec3> local_positions;
  std::vector<uint32_t> colors;
  std::vector<float> intensity;
  std::vector<uint32_t> classification;
  std::vector<uint32_t> point_index;
  std::vector<glm::vec3> normals;
  glm::dvec3 bounds_min{0.0}, bounds_max{0.0};
};

class PointCloud {
 public:
  // Copies and reorders the input into chunks, leaving out points with a
  // non-finite coordinate (skipped_nonfinite()). Throws Error on
  // inconsistent sizes. Besides the arrays it keeps, it needs 4 bytes per
  // point (the order) while it runs.
  explicit PointCloud(const PointCloudInput& input, uint32_t max_chunk_points = 16384);
  // Takes chunked points as they are (no reordering); throws Error when the
  // chunks do not tile the arrays or an attribute has the wrong size.
  explicit PointCloud(PointCloudChunks&& chunked);

  uint64_t id() const { return id_; }   // unique per cloud in the process
  size_t size() const { return local_positions_.size(); }
  // Input points left out for a non-finite coordinate (NaN, inf).
  size_t skipped_nonfinite() const { return skipped_nonfinite_; }
  const std::vector<PointChunk>& chunks() const { return chunks_; }
  const std::vector<glm::vec3>& local_positions() const { return local_positions_; }
  const std::vector<uint32_t>& colors() const { return colors_; }          // packed RGBA8, sRGB
  const std::vector<float>& intensity() const { return intensity_; }
  const std::vector<uint32_t>& classification() const { return classification_; }
  const std::vector<uint32_t>& point_index() const { return point_index_; }  // stable ids
  const std::vector<glm::vec3>& normals() const { return normals_; }
  bool has(Attribute a) const;
  glm::dvec3 bounds_min() const { return bounds_min_; }
  glm::dvec3 bounds_max() const { return bounds_max_; }
  const std::optional<glm::dvec3>& sensor() const { return sensor_; }  // see PointCloudInput
  // The splats' parameters in the cloud's order, or null: plain points.
  const GaussianSplats* gaussians() const { return gaussians_.get(); }
  // Reconstructs world-space (object-space) positions in double, in the
  // cloud's internal order.
  std::vector<double> positions_double() const;
  // Normals, curvature, neighbourhoods... computed on first request and
  // cached for the cloud's lifetime (geometry/analysis.h). The points never
  // change, so the cache never needs invalidating.
  geometry::Analysis& analysis() const;

 private:
  uint64_t id_;
  size_t skipped_nonfinite_ = 0;
  std::vector<PointChunk> chunks_;
  std::vector<glm::vec3> local_positions_;
  std::vector<uint32_t> colors_;
  std::vector<float> intensity_;
  std::vector<uint32_t> classification_;
  std::vector<uint32_t> point_index_;
  std::vector<glm::vec3> normals_;
  glm::dvec3 bounds_min_{0.0}, bounds_max_{0.0};
  std::optional<glm::dvec3> sensor_;
  std::shared_ptr<const GaussianSplats> gaussians_;
  mutable std::mutex analysis_mutex_;
  mutable std::shared_ptr<geometry::Analysis> analysis_;
};

}  // namespace pointnpr
