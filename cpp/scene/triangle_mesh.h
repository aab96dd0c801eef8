#pragma once
// A triangle mesh as the renderer sees it (Blender's evaluated meshes): one
// double-precision origin with float vertex offsets (like a cloud's chunk,
// so precision does not depend on where the mesh sits), triangles as vertex
// indices, and the optional colour sources of its surface: a colour per
// vertex or per triangle corner, UVs with a base-colour image, a base
// colour. Immutable once built; validated on construction.
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace pointnpr {

class PointCloud;

// Where a per-element attribute lives: per vertex, or per triangle corner
// (3 per triangle, Blender's face-corner domain).
enum class MeshDomain { Vertex = 0, Corner = 1 };

struct TriangleMeshInput {
  std::span<const double> positions;  // V*3, object space
  std::span<const uint32_t> indices;  // T*3, into the vertices
  std::span<const uint8_t> colors;    // V or 3T times channels, display sRGB; or empty
  int color_channels = 4;             // 3 or 4
  MeshDomain color_domain = MeshDomain::Vertex;
  std::span<const float> uvs;         // V*2 or 3T*2; or empty
  MeshDomain uv_domain = MeshDomain::Corner;
  std::span<const uint8_t> texture;   // texture_size.x * texture_size.y * 4, RGBA8 display sRGB, bottom row first
  glm::ivec2 texture_size{0, 0};
  bool has_base_color = false;
  glm::vec4 base_color{0.8f, 0.8f, 0.8f, 1.0f};  // display sRGB (the material's)
};

// Bounds of what a mesh may hold: nothing allocates without bound.
constexpr size_t kMaxMeshVertices = size_t(1) << 27;
constexpr size_t kMaxMeshTriangles = size_t(1) << 26;
constexpr int kMaxMeshTextureSide = 16384;
// At most this many points sampled from one mesh (surface sampling).
constexpr size_t kMaxSampledPoints = size_t(1) << 25;

class TriangleMesh {
 public:
  // Copies the input. Throws ParameterError on a non-finite coordinate or
  // UV, an index out of range, inconsistent or oversized arrays.
  explicit TriangleMesh(const TriangleMeshInput& input);

  uint64_t id() const { return id_; }  // unique per mesh in the process
  size_t num_vertices() const { return local_positions_.size(); }
  size_t num_triangles() const { return indices_.size() / 3; }
  glm::dvec3 origin() const { return origin_; }  // object space; vertices are offsets from it
  const std::vector<glm::vec3>& local_positions() const { return local_positions_; }
  const std::vector<uint32_t>& indices() const { return indices_; }
  const std::vector<uint32_t>& colors() const { return colors_; }  // packed RGBA8 display sRGB, or empty
  MeshDomain color_domain() const { return color_domain_; }
  const std::vector<glm::vec2>& uvs() const { return uvs_; }
  MeshDomain uv_domain() const { return uv_domain_; }
  const std::vector<uint32_t>& texture() const { return texture_; }  // packed RGBA8, or empty
  glm::ivec2 texture_size() const { return texture_size_; }
  bool has_colors() const { return !colors_.empty(); }
  bool has_texture() const { return !texture_.empty() && !uvs_.empty(); }
  bool has_base_color() const { return has_base_color_; }
  glm::vec4 base_color() const { return base_color_; }
  glm::vec3 local_min() const { return local_min_; }  // bounds of the offsets
  glm::vec3 local_max() const { return local_max_; }

  // Area-weighted vertex normals (object space, unit; zero where every
  // adjacent triangle is degenerate).
  std::vector<glm::vec3> vertex_normals() const;
  // The corner's colour/UV, whichever domain the attribute has.
  uint32_t corner_color(size_t corner) const {
    return colors_[color_domain_ == MeshDomain::Corner ? corner : indices_[corner]];
  }
  glm::vec2 corner_uv(size_t corner) const { return uvs_[uv_domain_ == MeshDomain::Corner ? corner : indices_[corner]]; }
  // The base-colour image at a UV (nearest texel, repeat wrapping).
  uint32_t texel(glm::vec2 uv) const;

  // The mesh's vertices as a point cloud (drawn as points; the cloud's
  // own normals are the vertex normals), made once and kept.
  std::shared_ptr<const PointCloud> vertex_cloud() const;
  // Points on the surface, `density` per square scene unit (object space),
  // seeded by triangle index: triangle t gets floor(area x density + u_t)
  // points (u_t a hash of t), at barycentric coordinates hashed from (t, j),
  // so the same mesh gives the same points in every frame and process.
  // Colours from the colour attribute, else the texture, else the base
  // colour; normals the triangle's. At most kMaxSampledPoints (the density
  // is lowered to fit; `capped` says so). The last density's cloud is kept.
  std::shared_ptr<const PointCloud> sampled_cloud(double density, bool* capped = nullptr) const;

 private:
  uint64_t id_;
  glm::dvec3 origin_{0.0};
  std::vector<glm::vec3> local_positions_;
  std::vector<uint32_t> indices_;
  std::vector<uint32_t> colors_;
  MeshDomain color_domain_ = MeshDomain::Vertex;
  std::vector<glm::vec2> uvs_;
  MeshDomain uv_domain_ = MeshDomain::Corner;
  std::vector<uint32_t> texture_;
  glm::ivec2 texture_size_{0, 0};
  bool has_base_color_ = false;
  glm::vec4 base_color_{0.8f};
  glm::vec3 local_min_{0.0f}, local_max_{0.0f};
  mutable std::mutex clouds_mutex_;
  mutable std::shared_ptr<const PointCloud> vertex_cloud_;
  mutable std::shared_ptr<const PointCloud> sampled_cloud_;
  mutable double sampled_density_ = -1.0;
  mutable bool sampled_capped_ = false;
};

// Points sampled on a mesh's surface (TriangleMesh::sampled_cloud without
// the cache): positions in object space (double), ids, colours, normals.
struct SurfaceSamples {
  std::vector<double> positions;  // N*3
  std::vector<uint8_t> colors;    // N*4
  std::vector<float> normals;     // N*3
  std::vector<uint32_t> ids;      // N, in triangle order
  bool capped = false;
};
SurfaceSamples sample_surface(const TriangleMesh& mesh, double density, size_t max_points = kMaxSampledPoints);

}  // namespace pointnpr
