#include "render/gpu_mesh.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "gl/device.h"
#include "render/gpu_cloud.h"  // pack_normals

namespace pointnpr {

const gl::Buffer* GpuMesh::find(MeshAttribute a) const {
  auto it = buffers.find(a);
  return it == buffers.end() || !it->second ? nullptr : &it->second;
}

template <class T>
gl::Buffer GpuMeshCache::upload(const std::vector<T>& data) {
  ++uploads_;
  return gl::make_buffer(data.size() * sizeof(T), data.data(), 0);
}

void GpuMeshCache::collect_garbage() {
  for (auto it = meshes_.begin(); it != meshes_.end();)
    it = it->second.source.expired() ? meshes_.erase(it) : std::next(it);
}

const GpuMesh* GpuMeshCache::find(uint64_t mesh_id) const {
  auto it = meshes_.find(mesh_id);
  return it == meshes_.end() ? nullptr : &it->second;
}

GpuMesh& GpuMeshCache::get(const std::shared_ptr<const TriangleMesh>& mesh, const std::set<MeshAttribute>& needed) {
  GpuMesh& g = meshes_[mesh->id()];
  const std::vector<uint32_t>& idx = mesh->indices();
  const size_t corners = idx.size();
  if (!g.positions) {
    g.source = mesh;
    std::vector<glm::vec3> unrolled(corners);
    for (size_t c = 0; c < corners; ++c) unrolled[c] = mesh->local_positions()[idx[c]];
    g.positions = upload(unrolled);
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    g.vao = gl::VertexArray(vao);
  }
  for (MeshAttribute a : needed) {
    if (g.buffers.count(a)) continue;
    gl::Buffer& buffer = g.buffers[a];  // stays empty where the mesh lacks the attribute
    switch (a) {
      case MeshAttribute::Normal: {
        const std::vector<glm::vec3> vertex = mesh->vertex_normals();
        std::vector<glm::vec3> unrolled(corners);
        for (size_t c = 0; c < corners; ++c) unrolled[c] = vertex[idx[c]];
        buffer = upload(pack_normals(unrolled));
        break;
      }
      case MeshAttribute::Color:
        if (mesh->has_colors()) {
          std::vector<uint32_t> unrolled(corners);
          for (size_t c = 0; c < corners; ++c) unrolled[c] = mesh->corner_color(c);
          buffer = upload(unrolled);
        }
        break;
      case MeshAttribute::Uv:
        if (!mesh->uvs().empty()) {
          std::vector<glm::vec2> unrolled(corners);
          for (size_t c = 0; c < corners; ++c) unrolled[c] = mesh->corner_uv(c);
          buffer = upload(unrolled);
        }
        break;
      case MeshAttribute::Texture:
        if (mesh->has_texture() && !g.texture.id()) {
          const glm::ivec2 size = mesh->texture_size();
          const int max_size = gl::Device::instance().info().max_texture_size;
          if (size.x > max_size || size.y > max_size)
            throw GLError("a mesh texture of " + std::to_string(size.x) + "x" + std::to_string(size.y) +
                          " is larger than this GPU's textures (" + std::to_string(max_size) + ")");
          int levels = 1;
          while ((std::max(size.x, size.y) >> levels) > 0) ++levels;
          g.texture = gl::Texture(GL_RGBA8, size, levels);
          glTextureSubImage2D(g.texture.id(), 0, 0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE,
                              mesh->texture().data());
          glGenerateTextureMipmap(g.texture.id());
          glTextureParameteri(g.texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
          glTextureParameteri(g.texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
          glTextureParameteri(g.texture.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
          glTextureParameteri(g.texture.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
          ++uploads_;
        }
        break;
    }
  }
  gl::check_gl("mesh upload");
  return g;
}

}  // namespace pointnpr
