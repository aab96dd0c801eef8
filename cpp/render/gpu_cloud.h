#pragma once
// GPU copies of point clouds: positions always, every other attribute only
// when a mark asks for it, computed once (through the cloud's geometry
// cache), uploaded once and kept per attribute key while the cloud lives.
// GL thread only.
#include <map>
#include <memory>
#include <string>

#include "gl/objects.h"
#include "render/attributes.h"
#include "scene/point_cloud.h"

namespace pointnpr {

// The surface a chunk's points sample (GpuCloud::host_chunk_surfaces).
struct ChunkSurface {
  double area = 0.0;         // cloud units squared; 0: unknown
  glm::dvec3 centre{0.0};    // the points' mean, chunk-local
};

struct GpuCloud {
  std::weak_ptr<const PointCloud> source;
  gl::Buffer positions;  // vec3 float offsets, chunk after chunk
  gl::VertexArray vao;   // positions as attribute 0 (GL_POINTS paths)
  bool own_normals = false;
  float intensity_scale = 1.0f;  // intensity_exposure() of the cloud's intensity
  std::map<AttributeKey, gl::Buffer> buffers;

  // The buffer of `key` (the cloud's own normals answer any k), or null when
  // it was not uploaded or the cloud lacks that source attribute.
  const gl::Buffer* find(AttributeKey key) const;
  // The resolution queue's order (queue_order()) on the host, computed on
  // first use and kept: the native rasterizer reads it there, the upload
  // of AttributeKind::QueueOrder takes it from here (sorted once).
  const std::vector<uint32_t>& host_queue_order() const;
  // The surface each chunk's points sample, chunk by chunk: what the
  // resolution queue's density follows where the chunk's box is larger than
  // its points (renderer.cpp). Computed on first use and kept.
  const std::vector<ChunkSurface>& host_chunk_surfaces() const;
  // Host data derived from the cloud and kept between frames while it
  // lives (the native marks', the chunks' surfaces): one T per name, made on
  // first use; the mark recomputes it in place when its inputs change, so
  // a parameter tweak never piles up copies.
  template <class T>
  T& host_slot(const std::string& name) const {
    std::shared_ptr<void>& slot = host_slots_[name];
    if (!slot) slot = std::make_shared<T>();
    return *std::static_pointer_cast<T>(slot);
  }

 private:
  mutable std::shared_ptr<const std::vector<uint32_t>> queue_order_;
  mutable std::map<std::string, std::shared_ptr<void>> host_slots_;
};

class GpuCloudCache {
 public:
  // The cloud with every attribute of `needed` it can have uploaded.
  GpuCloud& get(const std::shared_ptr<const PointCloud>& cloud, const AttributeSet& needed);
  void collect_garbage();  // drops clouds whose source is gone
  size_t size() const { return clouds_.size(); }
  uint64_t uploads() const { return uploads_; }  // buffers uploaded so far
  const GpuCloud* find(uint64_t cloud_id) const;

 private:
  template <class T>
  gl::Buffer upload(const std::vector<T>& data);
  std::map<uint64_t, GpuCloud> clouds_;
  uint64_t uploads_ = 0;
};

// Unit normals as signed 8-bit x, y, z (0.5 degree steps: plenty for
// shading and stroke directions, a quarter of the upload). Non-finite or
// zero normals pack to (0, 0, 0), which shaders read as "no normal".
// The scale from a cloud's intensity to display grey: its median at middle
// grey (gpu_cloud.cpp says why).
float intensity_exposure(std::vector<float> values);

std::vector<uint32_t> pack_normals(const std::vector<glm::vec3>& normals);
uint32_t pack_normal(glm::vec3 normal);
// As the shaders' unpackSnorm4x8(...).xyz: what a shader reads of a packed normal.
glm::vec3 unpack_normal(uint32_t packed);

// The continuous resolution queue (seed 001 sections 6.3, 7.2): for each
// chunk, its points' chunk-local indices ordered by queue_hash(point id ^
// kQueueSeed) (ties by index), so the first n of a chunk are the same
// points in every frame and process, and n + 1 adds exactly one point.
constexpr uint32_t kQueueSeed = 0x5eed001u;
uint32_t queue_hash(uint32_t x);  // lowbias32, as the shaders' hash_u32
std::vector<uint32_t> queue_order(const PointCloud& cloud);
// One chunk's: `order` gets the indices of ids[0, count) in queue order.
void chunk_queue_order(const uint32_t* ids, uint32_t count, uint32_t* order);
// Per chunk, the area its points sample (their count times the area a
// point of a planar sample of the chunk's median spacing, surface_resolution
// of 8 neighbours, stands for; 0 for a cloud of fewer than two points) and
// their mean position.
std::vector<ChunkSurface> chunk_surfaces(const PointCloud& cloud);

}  // namespace pointnpr
