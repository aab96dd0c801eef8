#include "render/gpu_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/hash.h"
#include "geometry/analysis.h"
#include "geometry/features.h"
#include "gl/device.h"
#include "scene/gaussian_splats.h"
#include "scene/splat_attributes.h"

namespace pointnpr {

uint32_t pack_normal(glm::vec3 n) {
  const float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  if (!std::isfinite(len) || len < 1e-6f) return 0;  // 0: no usable normal
  uint32_t packed = 0;
  for (int c = 0; c < 3; ++c) {
    const float v = std::clamp(n[c] / len, -1.0f, 1.0f);
    packed |= uint32_t(uint8_t(int8_t(std::lround(v * 127.0f)))) << (8 * c);
  }
  return packed;
}

glm::vec3 unpack_normal(uint32_t packed) {
  glm::vec3 n;
  for (int c = 0; c < 3; ++c) n[c] = std::max(float(int8_t(uint8_t(packed >> (8 * c)))) / 127.0f, -1.0f);
  return n;
}

std::vector<uint32_t> pack_normals(const std::vector<glm::vec3>& normals) {
  std::vector<uint32_t> out(normals.size());
  for (size_t i = 0; i < normals.size(); ++i) out[i] = pack_normal(normals[i]);
  return out;
}

uint32_t queue_hash(uint32_t x) { return hash_u32(x); }

void chunk_queue_order(const uint32_t* ids, uint32_t count, uint32_t* order) {
  std::vector<std::pair<uint32_t, uint32_t>> keyed(count);
  for (uint32_t i = 0; i < count; ++i) keyed[i] = {queue_hash(ids[i] ^ kQueueSeed), i};
  std::sort(keyed.begin(), keyed.end());  // ties (equal hashes) by index: a total order
  for (uint32_t i = 0; i < count; ++i) order[i] = keyed[i].second;
}

std::vector<uint32_t> queue_order(const PointCloud& cloud) {
  std::vector<uint32_t> order(cloud.size());
  for (const PointChunk& chunk : cloud.chunks())
    chunk_queue_order(cloud.point_index().data() + chunk.first, chunk.count, order.data() + chunk.first);
  return order;
}

const std::vector<uint32_t>& GpuCloud::host_queue_order() const {
  if (!queue_order_) {
    const std::shared_ptr<const PointCloud> cloud = source.lock();
    if (!cloud) throw Error("the queue order of a cloud that is gone");
    queue_order_ = std::make_shared<const std::vector<uint32_t>>(queue_order(*cloud));
  }
  return *queue_order_;
}

std::vector<ChunkSurface> chunk_surfaces(const PointCloud& cloud) {
  // A planar Poisson sample of density rho has its 8 nearest neighbours at
  // a mean distance of 1.113 / sqrt(rho) (the mean over j <= 8 of
  // Gamma(j + 1/2) / (Gamma(j) sqrt(pi))): a point stands for (r / 1.113)^2.
  // The chunk's median r, so its few isolated points (each with a large r
  // of its own) do not count as surface.
  constexpr int kNeighbors = 8;
  constexpr double kAreaPerSquaredSpacing = 1.0 / (1.1128 * 1.1128);
  std::vector<ChunkSurface> areas(cloud.chunks().size());
  if (cloud.size() < 2) return areas;
  const std::vector<float>& r = cloud.analysis().surface_resolution(kNeighbors)->r;
  std::vector<float> chunk_r;
  for (size_t c = 0; c < areas.size(); ++c) {
    const PointChunk& chunk = cloud.chunks()[c];
    if (chunk.count == 0) continue;
    chunk_r.assign(r.begin() + chunk.first, r.begin() + chunk.first + chunk.count);
    std::nth_element(chunk_r.begin(), chunk_r.begin() + chunk.count / 2, chunk_r.end());
    const double median = chunk_r[chunk.count / 2];
    if (std::isfinite(median)) areas[c].area = double(chunk.count) * median * median * kAreaPerSquaredSpacing;
    glm::dvec3 sum(0.0);
    for (uint32_t i = chunk.first; i < chunk.first + chunk.count; ++i) sum += glm::dvec3(cloud.local_positions()[i]);
    areas[c].centre = sum / double(chunk.count);
  }
  return areas;
}

const std::vector<ChunkSurface>& GpuCloud::host_chunk_surfaces() const {
  std::vector<ChunkSurface>& surfaces = host_slot<std::vector<ChunkSurface>>("chunk_surfaces");
  if (surfaces.empty()) {
    const std::shared_ptr<const PointCloud> cloud = source.lock();
    if (!cloud) throw Error("the surface areas of a cloud that is gone");
    surfaces = chunk_surfaces(*cloud);
  }
  return surfaces;
}

const gl::Buffer* GpuCloud::find(AttributeKey key) const {
  if (key.attribute == AttributeKind::Normal && own_normals) key.k = 0;
  if (is_source_attribute(key.attribute) && key.attribute != AttributeKind::Normal) key.k = 0;
  auto it = buffers.find(key);
  return it == buffers.end() || !it->second ? nullptr : &it->second;
}

template <class T>
gl::Buffer GpuCloudCache::upload(const std::vector<T>& data) {
  ++uploads_;
  return gl::make_buffer(data.size() * sizeof(T), data.data(), 0);
}

void GpuCloudCache::collect_garbage() {
  for (auto it = clouds_.begin(); it != clouds_.end();)
    it = it->second.source.expired() ? clouds_.erase(it) : std::next(it);
}

const GpuCloud* GpuCloudCache::find(uint64_t cloud_id) const {
  auto it = clouds_.find(cloud_id);
  return it == clouds_.end() ? nullptr : &it->second;
}

// Exposure chosen from the scan's intensity histogram: its median lands on
// middle grey (18 % reflectance, display sRGB 0.46), where an RGB scan's
// median sits. Aerial intensity is skewed (rare glints of retro-reflectors
// far above the rest): white at the 99th percentile, as before, left the
// median of such tiles near black. Values above about twice the median
// clip. Scans whose median is 0 (mostly unset) keep white at the 99th
// percentile, else at the peak.
float intensity_exposure(std::vector<float> values) {
  constexpr float kMiddleGrey = 0.4614f;  // sRGB encoding of 0.18 linear
  if (values.empty()) return 1.0f;
  const auto middle = values.begin() + long(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (*middle > 0.0f) return kMiddleGrey / *middle;
  float top = geometry::percentile99(values);
  if (!(top > 0.0f))
    for (float v : values) top = std::max(top, v);
  return top > 0.0f ? 1.0f / top : 1.0f;
}

GpuCloud& GpuCloudCache::get(const std::shared_ptr<const PointCloud>& cloud, const AttributeSet& needed) {
  GpuCloud& g = clouds_[cloud->id()];
  if (!g.positions) {
    g.source = cloud;
    g.own_normals = cloud->has(Attribute::Normal);
    g.positions = upload(cloud->local_positions());
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    g.vao = gl::VertexArray(vao);
    glVertexArrayVertexBuffer(vao, 0, g.positions.id(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
  }
  for (AttributeKey key : needed) {
    if (key.attribute == AttributeKind::AutoColor) {
      // Stands for the first colour attribute the cloud has.
      key.attribute = cloud->has(Attribute::Color)       ? AttributeKind::Color
                      : cloud->has(Attribute::Intensity) ? AttributeKind::Intensity
                                                         : AttributeKind::Classification;
    }
    // Source attributes have no k; the cloud's own normals serve every k.
    if (is_source_attribute(key.attribute) && key.attribute != AttributeKind::Normal) key.k = 0;
    if (key.attribute == AttributeKind::Normal && g.own_normals) key.k = 0;
    if (g.buffers.count(key)) continue;
    gl::Buffer& buffer = g.buffers[key];  // stays empty where the cloud lacks a source attribute
    geometry::Analysis* analysis = is_source_attribute(key.attribute) && key.k == 0 ? nullptr : &cloud->analysis();
    switch (key.attribute) {
      case AttributeKind::Color:
        if (cloud->has(Attribute::Color)) buffer = upload(cloud->colors());
        break;
      case AttributeKind::Intensity:
        if (cloud->has(Attribute::Intensity)) {
          buffer = upload(cloud->intensity());
          g.intensity_scale = intensity_exposure(cloud->intensity());
        }
        break;
      case AttributeKind::Classification:
        if (cloud->has(Attribute::Classification)) buffer = upload(cloud->classification());
        break;
      case AttributeKind::AutoColor: break;  // resolved above
      case AttributeKind::PointId: buffer = upload(cloud->point_index()); break;
      case AttributeKind::Normal:
        if (key.k == 0) {
          buffer = upload(pack_normals(cloud->normals()));
        } else {
          // Consistently oriented; marks treat them as two-sided anyway.
          buffer = upload(pack_normals(*analysis->normals({key.k, geometry::Orientation::Consistent, {}})));
        }
        break;
      case AttributeKind::Curvature: buffer = upload(*analysis->curvature(key.k)); break;
      case AttributeKind::LocalResolution: buffer = upload(analysis->surface_resolution(key.k)->r); break;
      case AttributeKind::FeatureDegree: {
        const FeatureDegreeSpec spec = feature_degree_spec(key);
        buffer = upload(*analysis->feature_degree(spec.neighbors, {spec.color_weight}));
        break;
      }
      case AttributeKind::QueueOrder:
        // Kept on the host where the native rasterizer (software devices) reads it too.
        buffer = upload(gl::Device::instance().info().software ? g.host_queue_order() : queue_order(*cloud));
        break;
      case AttributeKind::FeatureLine: {
        const FeatureLineSpec spec = feature_line_spec(key);
        const std::vector<float>& degree =
            *analysis->feature_degree(spec.degree.neighbors, {spec.degree.color_weight});
        std::vector<uint8_t> mask(degree.size());
        for (size_t i = 0; i < degree.size(); ++i) mask[i] = degree[i] >= spec.threshold ? 1 : 0;
        const geometry::LineFit fit = analysis->line_fit(mask, spec.line_neighbors);
        // Per point: the line (direction, error), its chain link (unit
        // direction to its parent, flags), the link's length (float bits).
        const std::vector<uint32_t> lines = pack_normals(fit.direction);
        std::vector<glm::vec3> link_dir(lines.size(), glm::vec3(0.0f));
        for (size_t i = 0; i < lines.size(); ++i)
          if (fit.to_parent[i] != glm::vec3(0.0f)) link_dir[i] = glm::normalize(fit.to_parent[i]);
        const std::vector<uint32_t> links = pack_normals(link_dir);
        std::vector<uint32_t> packed(3 * lines.size());
        for (size_t i = 0; i < lines.size(); ++i) {
          const float e = std::isfinite(fit.error[i]) ? std::clamp(fit.error[i], 0.0f, 1.0f) : 1.0f;
          packed[3 * i] = (lines[i] & 0x00ffffffu) | (uint32_t(std::lround(e * 255.0f)) << 24);
          const float length = glm::length(fit.to_parent[i]);
          const uint32_t flags = length > 0.0f ? kFeatureChainLinked | fit.chain_end[i] : 0u;
          packed[3 * i + 1] = (links[i] & 0x00ffffffu) | (flags << 24);
          std::memcpy(&packed[3 * i + 2], &length, 4);
        }
        buffer = upload(packed);
        break;
      }
      case AttributeKind::ResolutionDeviation: buffer = upload(analysis->surface_resolution(key.k)->eps); break;
      case AttributeKind::PrincipalAxis:
        if (const GaussianSplats* splats = cloud->gaussians()) {
          // A splat's own frame: its longest axis (seed 004's brush direction).
          buffer = upload(pack_normals(splat_axes(*splats, true)));
        } else {
          buffer = upload(pack_normals(analysis->points().to_original(analysis->pca(key.k)->major)));
        }
        break;
      case AttributeKind::RadiusNormal:
        if (g.own_normals) {
          buffer = upload(pack_normals(cloud->normals()));
        } else {
          geometry::NormalOptions o{key.k, geometry::Orientation::Consistent, {}};
          o.radius_factor = 3.0;
          buffer = upload(pack_normals(*analysis->normals(o)));
        }
        break;
      case AttributeKind::ClusterShape: {
        const auto shapes = analysis->cluster_shapes(key.k);
        const std::vector<uint32_t> axes = pack_normals(shapes->axis);
        std::vector<uint32_t> packed(4 * axes.size());
        for (size_t i = 0; i < axes.size(); ++i) {
          uint32_t elongation = 0;
          std::memcpy(&elongation, &shapes->elongation[i], 4);
          packed[4 * i] = axes[i];
          packed[4 * i + 1] = elongation;
          packed[4 * i + 2] = shapes->size[i];
          packed[4 * i + 3] = uint32_t(shapes->label[i]);
        }
        buffer = upload(packed);
        break;
      }
      case AttributeKind::SplatRadius: buffer = upload(splat_radii(*cloud, key.k)); break;
      case AttributeKind::SplatOpacity: buffer = upload(splat_opacities(*cloud)); break;
    }
  }
  gl::check_gl("point upload");
  return g;
}

}  // namespace pointnpr
