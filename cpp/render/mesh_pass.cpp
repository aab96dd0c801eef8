#include "render/mesh_pass.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "marks/mesh_surface/mesh_surface.h"
#include "render/box_projection.h"

namespace pointnpr {

MeshPass prepare_meshes(const Segment& seg, const Camera& cam, glm::ivec2 size, GpuMeshCache& cache) {
  MeshPass out;
  const ParamValues& surface = seg.style.surface.params;
  const MeshMode mode = mesh_mode(surface);
  const std::set<MeshAttribute> needed = mesh_attributes(surface);
  for (const Instance& inst : seg.instances) {
    if (!inst.mesh) {
      out.point_instances.push_back(inst);
      continue;
    }
    const TriangleMesh& mesh = *inst.mesh;
    if (mesh.num_vertices() == 0) continue;
    if (mode != MeshMode::Surface || mesh.num_triangles() == 0) {
      Instance points = inst;
      points.mesh = nullptr;
      if (mode == MeshMode::Sampled && mesh.num_triangles() > 0) {
        bool capped = false;
        points.cloud = mesh.sampled_cloud(mesh_sample_density(surface), &capped);
        if (capped)
          out.warnings.push_back((inst.name.empty() ? "a mesh of segment '" + seg.name + "'" : "'" + inst.name + "'") +
                                 ": surface sampling capped at " + std::to_string(kMaxSampledPoints) +
                                 " points (lower sample_density)");
      } else {
        points.cloud = mesh.vertex_cloud();
      }
      out.point_instances.push_back(std::move(points));
      continue;
    }
    // Cull the mesh's box in double, as chunks are culled.
    const glm::dmat4 view_from_mesh =
        cam.view_from_world * inst.world_from_object * glm::translate(glm::dmat4(1.0), mesh.origin());
    const ProjectedBox box = project_box(view_from_mesh, glm::dvec3(mesh.local_min()), glm::dvec3(mesh.local_max()),
                                         cam, size);
    const Rect r = box.rect(size, 1.0);
    if (box.all_near || box.all_far || r.empty()) continue;
    const GpuMesh& gpu = cache.get(inst.mesh, needed);
    out.visible.push_back({&gpu, &mesh, view_from_mesh});
    out.screen = out.screen.united(r);
    out.depth_min = std::min(out.depth_min, std::max(box.depth_min, cam.clip_start));
    out.depth_max = std::max(out.depth_max, std::min(box.depth_max, cam.clip_end));
    out.triangles += mesh.num_triangles();
  }
  return out;
}

}  // namespace pointnpr
