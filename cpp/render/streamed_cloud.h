#pragma once
// Out-of-core scans in a frame: each cached instance (Instance::cached)
// draws, within its cloud's point budget, a prefix of the resolution queue
// of every chunk it sees, sized by the chunk's projected area (seed 001's
// constant screen density), streamed from the cache's mapping.
#include <glm/glm.hpp>
#include <vector>

#include "render/style.h"
#include "scene/camera.h"
#include "scene/cached_cloud.h"

namespace pointnpr {

// Per chunk of `cache`: the pixels of the frame its box covers (the
// rectangle of its projected corners, clipped to the frame; the whole frame
// where it crosses the camera plane), 0 where it is out of view.
std::vector<double> chunk_view_weights(const io::ScanCache& cache, const glm::dmat4& view_from_object,
                                       const Camera& cam, glm::ivec2 frame);

// `scene`, or a copy in `storage` whose cached instances hold the cloud
// their view draws this frame (a cached instance's `cloud` is ignored).
// Each streams up to `frame_budget` points (the frame's point budget), or
// its cloud's own budget where the frame has none (0).
const Scene& with_streamed_clouds(const Scene& scene, const Camera& cam, glm::ivec2 frame, Scene& storage,
                                  uint64_t frame_budget = 0);

}  // namespace pointnpr
