#pragma once
// A segment's meshes before its marks draw (render/renderer.cpp): the ones
// the style draws as surfaces culled and uploaded for the mesh_surface
// mark; the others (vertex-only meshes, and every mesh where the style asks
// for points or surface samples) turned into cloud instances for the
// style's point mark. GL thread only.
#include <string>
#include <vector>

#include "render/mark.h"
#include "render/style.h"
#include "scene/camera.h"

namespace pointnpr {

struct MeshPass {
  std::vector<Instance> point_instances;  // the segment's clouds, then meshes drawn as points
  std::vector<VisibleMesh> visible;       // meshes drawn as surfaces that survived culling
  Rect screen;                            // their conservative screen rectangle
  double depth_min = 1e300, depth_max = 0.0;
  size_t triangles = 0;
  std::vector<std::string> warnings;
};

MeshPass prepare_meshes(const Segment& seg, const Camera& cam, glm::ivec2 size, GpuMeshCache& cache);

}  // namespace pointnpr
