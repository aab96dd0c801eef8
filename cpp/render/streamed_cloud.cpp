#include "render/streamed_cloud.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>

#include "render/box_projection.h"

namespace pointnpr {

namespace {
// Chunks this close outside the frame still count: their splats reach in.
constexpr double kViewMarginPixels = 32.0;
}  // namespace

std::vector<double> chunk_view_weights(const io::ScanCache& cache, const glm::dmat4& view_from_object,
                                       const Camera& cam, glm::ivec2 frame) {
  std::vector<double> weights;
  weights.reserve(cache.chunks().size());
  const glm::dvec2 size(frame);
  for (const io::ScanCacheChunk& c : cache.chunks()) {
    const glm::dmat4 view_from_chunk = view_from_object * glm::translate(glm::dmat4(1.0), c.origin);
    const ProjectedBox box = project_box(view_from_chunk, glm::dvec3(c.local_min), glm::dvec3(c.local_max), cam, frame);
    if (box.all_near || box.all_far || box.rect(frame, kViewMarginPixels).empty()) {
      weights.push_back(0.0);
      continue;
    }
    if (box.crosses_near) {
      weights.push_back(size.x * size.y);
      continue;
    }
    const glm::dvec2 extent = glm::clamp(box.hi, glm::dvec2(0.0), size) - glm::clamp(box.lo, glm::dvec2(0.0), size);
    weights.push_back(std::max(1.0, extent.x * extent.y));  // at least a pixel: a far chunk still shows
  }
  return weights;
}

const Scene& with_streamed_clouds(const Scene& scene, const Camera& cam, glm::ivec2 frame, Scene& storage,
                                  uint64_t frame_budget) {
  const bool any = std::any_of(scene.segments.begin(), scene.segments.end(), [](const Segment& s) {
    return std::any_of(s.instances.begin(), s.instances.end(), [](const Instance& i) { return bool(i.cached); });
  });
  if (!any) return scene;
  storage = scene;
  for (Segment& seg : storage.segments)
    for (Instance& inst : seg.instances) {
      if (!inst.cached) continue;
      const CachedCloud& cached = *inst.cached;
      const glm::dmat4 view_from_object = cam.view_from_world * inst.world_from_object;
      const std::vector<double> weights = chunk_view_weights(cached.cache(), view_from_object, cam, frame);
      const uint64_t budget = frame_budget > 0 ? frame_budget : cached.point_budget();
      inst.cloud = cached.stream(cached.counts_for(weights, budget));
    }
  return storage;
}

}  // namespace pointnpr
