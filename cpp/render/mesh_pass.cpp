#include "render/mesh_pass.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "marks/mesh_surface.h"

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
    const glm::dvec3 lo_box(mesh.local_min()), hi_box(mesh.local_max());
    bool all_near = true, all_far = true, crosses_near = false;
    double dmin = std::numeric_limits<double>::max(), dmax = 0.0;
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner((c & 1) ? hi_box.x : lo_box.x, (c & 2) ? hi_box.y : lo_box.y,
                              (c & 4) ? hi_box.z : lo_box.z);
      const glm::dvec4 v = view_from_mesh * glm::dvec4(corner, 1.0);
      const double dist = -v.z;
      dmin = std::min(dmin, dist);
      dmax = std::max(dmax, dist);
      all_near = all_near && dist < cam.clip_start;
      all_far = all_far && dist > cam.clip_end;
      if (!cam.orthographic && dist < cam.clip_start * 0.5) {
        crosses_near = true;
        continue;
      }
      const glm::dvec4 clip = cam.projection * v;
      const glm::dvec2 win = (glm::dvec2(clip) / clip.w * 0.5 + 0.5) * glm::dvec2(size);
      lo = glm::min(lo, win);
      hi = glm::max(hi, win);
    }
    Rect r;
    if (crosses_near) {
      r = Rect{{0, 0}, size};
    } else {
      r.min = glm::ivec2(glm::max(glm::floor(lo - 1.0), glm::dvec2(0.0)));
      r.max = glm::ivec2(glm::min(glm::ceil(hi + 1.0), glm::dvec2(size)));
    }
    if (all_near || all_far || r.empty()) continue;
    const GpuMesh& gpu = cache.get(inst.mesh, needed);
    out.visible.push_back({&gpu, &mesh, glm::mat4(view_from_mesh)});
    out.screen = out.screen.united(r);
    out.depth_min = std::min(out.depth_min, std::max(dmin, cam.clip_start));
    out.depth_max = std::max(out.depth_max, std::min(dmax, cam.clip_end));
    out.triangles += mesh.num_triangles();
  }
  return out;
}

}  // namespace pointnpr
