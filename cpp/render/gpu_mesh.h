#pragma once
// GPU copies of triangle meshes, like GpuCloud for clouds: positions once
// per mesh, unrolled to one vertex per triangle corner (so per-corner
// colours and UVs need no index juggling, and flat shading is free); every
// other attribute only when the mesh_surface mark asks for it, uploaded once
// and kept while the mesh lives. GL thread only.
#include <map>
#include <memory>
#include <set>

#include "gl/objects.h"
#include "scene/triangle_mesh.h"

namespace pointnpr {

// What the mesh_surface mark reads with its current parameters.
enum class MeshAttribute : uint8_t { Normal, Color, Uv, Texture };

struct GpuMesh {
  std::weak_ptr<const TriangleMesh> source;
  gl::Buffer positions;  // vec3 float offsets from the mesh origin, per corner
  gl::VertexArray vao;   // empty: the shaders read the buffers by gl_VertexID
  std::map<MeshAttribute, gl::Buffer> buffers;  // normals (snorm8 x3), colours (RGBA8), uvs (vec2), per corner
  gl::Texture texture;   // the base-colour image (RGBA8, mipmapped), when asked for and present

  const gl::Buffer* find(MeshAttribute a) const;
};

class GpuMeshCache {
 public:
  GpuMesh& get(const std::shared_ptr<const TriangleMesh>& mesh, const std::set<MeshAttribute>& needed);
  void collect_garbage();  // drops meshes whose source is gone
  size_t size() const { return meshes_.size(); }
  uint64_t uploads() const { return uploads_; }  // buffers and textures uploaded so far
  const GpuMesh* find(uint64_t mesh_id) const;

 private:
  template <class T>
  gl::Buffer upload(const std::vector<T>& data);
  std::map<uint64_t, GpuMesh> meshes_;
  uint64_t uploads_ = 0;
};

}  // namespace pointnpr
