#include "render/renderer.h"

#include <algorithm>
#include <optional>
#include <chrono>
#include <cmath>
#include <deque>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>

#include "gl/device.h"
#include "gl/objects.h"
#include "gl/shaders.h"
#include "marks/mesh_surface/mesh_surface.h"
#include "render/box_projection.h"
#include "render/point_budget.h"
#include "render/segment_stages.h"
#include "render/filter_chain.h"
#include "render/frame_targets.h"
#include "render/frame_warnings.h"
#include "render/gpu_cloud.h"
#include "render/image_textures.h"
#include "render/mesh_pass.h"
#include "render/streamed_cloud.h"
#include "render/tiling.h"

namespace pointnpr {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

const float kInf = std::numeric_limits<float>::infinity();

// The pixels a chunk's sampled surface covers seen face-on at the depth
// of its points' mean; negative where unknown. The queue's M where
// the box's hull is more: the density on screen then follows the points,
// not the empty space a chunk's box holds (a Morton run across two
// regions, a tree over flat ground).
double points_area(const ChunkSurface& surface, const glm::dmat4& view_from_chunk, const Camera& cam, int height) {
  const double area = surface.area;
  const double depth = -(view_from_chunk * glm::dvec4(surface.centre, 1.0)).z;
  if (!(area > 0.0) || (!cam.orthographic && !(depth > 0.0))) return -1.0;
  // An instance's scale: lengths grow by the cube root of the linear part's determinant.
  const double px = cam.pixels_per_unit(depth, height) *
                    std::cbrt(std::abs(glm::determinant(glm::dmat3(view_from_chunk))));
  return area * px * px;
}

}  // namespace

TilePlan plan_frame_tiles(const Scene& scene, const RenderSettings& s, std::vector<std::string>& warnings);

struct Renderer::Impl {
  gl::ShaderLibrary shaders;
  FrameWarnings frame_warnings;
  ImageTextures images;
  std::shared_ptr<BufferPool> pool = std::make_shared<BufferPool>();
  GpuCloudCache clouds;
  GpuMeshCache meshes;
  FrameTargets targets;
  ScratchBuffers mark_buffers;
  HostScratch host;  // the native marks' images and scratch, kept between frames
  // The frame being drawn: its size, and the tile whose region the images
  // hold (frame pixels [origin, origin + targets.size)).
  glm::ivec2 frame{0, 0};
  glm::ivec2 origin{0, 0};

  void begin_frame(const RenderSettings& s, const TilePlan& plan, RenderResult& result) {
    clouds.collect_garbage();
    meshes.collect_garbage();
    frame_warnings = FrameWarnings();
    frame = {s.width, s.height};
    targets.ensure(plan.region_size, gl::Device::instance().info().int64_atomics && s.int64_atomics);
    const size_t pixels = size_t(s.width) * size_t(s.height);
    result.width = s.width;
    result.height = s.height;
    result.pool = pool;
    result.color = pool->take_floats(pixels * 4);
    result.depth = pool->take_floats(pixels);
    result.segment_index = pool->take_ints(pixels);
  }

  void begin_tile(const Tile& tile) {
    origin = tile.region.min;
    pixel_origin() = origin;
    const Rect all{{0, 0}, targets.size};
    const float zero4[4] = {0, 0, 0, 0};
    const int32_t minus_one = -1;
    clear_texture_rect(targets.accum, all, zero4, GL_RGBA, GL_FLOAT);
    clear_texture_rect(targets.accum_depth, all, &kInf, GL_RED, GL_FLOAT);
    clear_texture_rect(targets.accum_index, all, &minus_one, GL_RED_INTEGER, GL_INT);
    const int32_t zero = 0;
    clear_texture_rect(targets.accum_added, all, &zero, GL_RED_INTEGER, GL_INT);
    gl::check_gl("frame start");
  }

  struct Culled {
    std::vector<VisibleChunk> chunks;
    std::vector<Rect> rects;  // per chunk: its conservative frame rectangle
    Rect screen;  // conservative frame rectangle the marks can touch
    double depth_min = std::numeric_limits<double>::max(), depth_max = 0.0;
    // The segment's meshes drawn as surfaces (their clouds, for meshes drawn
    // as points, are kept alive here: `chunks` points into them).
    MeshPass meshes;
    mutable std::unique_ptr<MarkFrameCache> mark_cache;  // the mark's, for the frame's tiles
  };

  // A segment's meshes and chunks, once per frame, in frame pixels.
  Culled cull_segment(const Segment& seg, const Camera& cam, RenderResult& result) {
    MeshPass mesh_pass = prepare_meshes(seg, cam, frame, meshes);
    result.warnings.insert(result.warnings.end(), mesh_pass.warnings.begin(), mesh_pass.warnings.end());
    Culled out = cull(seg, mesh_pass.point_instances, cam, result);
    result.stats["triangles_drawn"] += double(mesh_pass.triangles);
    out.meshes = std::move(mesh_pass);
    return out;
  }

  // Culls chunks (their bounds grown by the mark's extent) against the view
  // volume, in double; uploads what the mark needs for the survivors' clouds.
  Culled cull(const Segment& seg, const std::vector<Instance>& instances, const Camera& cam, RenderResult& result) {
    Culled out;
    const AttributeSet needed = seg.style.attributes();
    // A streamed cloud is new whenever the view changes its counts: no
    // per-point spacing for it (a kNN per such frame; segment_sampling alike).
    const AttributeSet needed_streamed = seg.style.mark.mark->attributes(seg.style.mark.params);
    const MarkExtent extent = seg.style.mark.mark->extent(seg.style.mark.params);
    uint32_t key_base = 0;
    int total = 0, culled = 0;
    const glm::ivec2 size = frame;
    const double margin = double(extent.pixels);
    const bool queued = queue_enabled(seg.style.mark.params);
    for (const Instance& inst : instances) {
      if (inst.cloud && inst.cloud->skipped_nonfinite() > 0) frame_warnings.add_nonfinite(inst, seg);
      if (!inst.cloud || inst.cloud->size() == 0) continue;
      GpuCloud* gpu = nullptr;
      const std::vector<ChunkSurface>* surfaces = nullptr;  // the queue's, once per cloud
      const glm::dmat4 view_from_object = cam.view_from_world * inst.world_from_object;
      for (const PointChunk& chunk : inst.cloud->chunks()) {
        ++total;
        const glm::dmat4 view_from_chunk = view_from_object * glm::translate(glm::dmat4(1.0), chunk.origin);
        const glm::dvec3 lo_box = glm::dvec3(chunk.local_min) - extent.world;
        const glm::dvec3 hi_box = glm::dvec3(chunk.local_max) + extent.world;
        const ProjectedBox box = project_box(view_from_chunk, lo_box, hi_box, cam, size);
        const Rect r = box.rect(size, margin);
        if (box.all_near || box.all_far || r.empty()) {
          ++culled;
          key_base += chunk.count;
          continue;
        }
        if (!gpu) {
          gpu = &clouds.get(inst.cloud, inst.cached ? needed_streamed : needed);
          const std::string missing = missing_color(needed, *gpu);
          if (!missing.empty()) frame_warnings.add_missing_color(missing, inst, seg);
        }
        out.screen = out.screen.united(r);
        out.depth_min = std::min(out.depth_min, std::max(box.depth_min, cam.clip_start));
        out.depth_max = std::max(out.depth_max, std::min(box.depth_max, cam.clip_end));
        double area = box.crosses_near ? -1.0 : box.hull_area();
        if (queued && area >= 0.0) {
          if (!surfaces) surfaces = &gpu->host_chunk_surfaces();
          const double points =
              points_area(surfaces->at(size_t(&chunk - inst.cloud->chunks().data())), view_from_chunk, cam, size.y);
          if (points >= 0.0) area = std::min(area, points);
        }
        out.chunks.push_back({gpu, &chunk, glm::mat4(view_from_chunk), key_base, area});
        out.rects.push_back(r);
        key_base += chunk.count;
      }
    }
    for (const VisibleChunk& v : out.chunks) result.stats["points_drawn"] += double(v.chunk->count);
    result.stats["chunks_total"] += total;
    result.stats["chunks_culled"] += culled;
    return out;
  }

  // The frame's point budget over every segment's visible chunks: each cut
  // short draws a prefix of its queue order, which its cloud then uploads.
  void apply_point_budget(const Scene& scene, std::vector<Culled>& culled, uint64_t budget, RenderResult& result) {
    std::vector<BudgetChunk> chunks;
    const double frame_area = double(frame.x) * double(frame.y);
    for (size_t i = 0; i < culled.size(); ++i)
      for (const VisibleChunk& v : culled[i].chunks)
        // A chunk across the camera plane may fill the frame.
        chunks.push_back({queue_count(v, scene.segments[i].style.mark.params),
                          v.screen_area >= 0.0 ? std::max(v.screen_area, 1.0) : frame_area});
    const BudgetPlan plan = plan_point_budget(chunks, budget);
    result.stats["point_budget_points"] = double(plan.drawn);
    if (!plan.applied) return;
    result.stats["point_budget_level"] = plan.level;
    size_t k = 0;
    for (Culled& c : culled)
      for (VisibleChunk& v : c.chunks) {
        v.budget_count = plan.counts[k++];
        // Every visible cloud: a mark drawing by the queue reads the order
        // of each of its chunks, cut short or not.
        if (!v.gpu->find({AttributeKind::QueueOrder}))
          if (const auto cloud = v.gpu->source.lock()) clouds.get(cloud, {{AttributeKind::QueueOrder}});
      }
  }

  MarkTargets mark_targets() {
    MarkTargets t;
    t.size = targets.size;
    t.origin = origin;
    t.frame_size = frame;
    t.int64_atomics = targets.int64;
    t.color = &targets.raster_color;
    t.depth = &targets.raster_depth;
    t.gl_depth = &targets.gl_depth;
    t.fbo = targets.fbo.id();
    t.depth_keys = &targets.depth_keys;
    t.keys = &targets.keys;
    t.scratch = [this](GLenum format, int index) -> const gl::Texture& { return targets.mark_scratch(format, index); };
    t.scratch_buffer = [this](size_t bytes, int index) -> const gl::Buffer& { return mark_buffers.get(bytes, index); };
    return t;
  }

  // Tight bounds of the covered pixels inside `search`.
  Rect coverage_bounds(const Rect& search) {
    const int32_t init[4] = {std::numeric_limits<int32_t>::max(), std::numeric_limits<int32_t>::max(), -1, -1};
    glNamedBufferSubData(targets.bbox.id(), 0, sizeof(init), init);
    const gl::Program& p = shaders.compute("coverage_bounds.comp");
    glBindImageTexture(0, targets.raster_depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, targets.bbox.id());
    dispatch_rect(p, search);
    int32_t box[4];
    glGetNamedBufferSubData(targets.bbox.id(), 0, sizeof(box), box);
    if (box[2] < 0) return Rect{};
    return Rect{{box[0], box[1]}, {box[2], box[3]}};
  }

  // The frame surface-anchored filter patterns stick to: the first
  // instance's object space, centred on its cloud (fixed for the cloud's
  // life, so the pattern is the same in every frame).
  static glm::dmat4 surface_anchor(const Segment& seg) {
    for (const Instance& inst : seg.instances) {
      if (inst.cloud && inst.cloud->size() > 0)
        return inst.world_from_object *
               glm::translate(glm::dmat4(1.0), 0.5 * (inst.cloud->bounds_min() + inst.cloud->bounds_max()));
      if (inst.mesh && inst.mesh->num_vertices() > 0)
        return inst.world_from_object * glm::translate(glm::dmat4(1.0), inst.mesh->origin());
    }
    return glm::dmat4(1.0);
  }

  // The frame's chunks that reach the tile's region, and their rectangle in
  // the tile's pixels (the depth range stays the frame's: marks see the
  // same numbers in every tile).
  Culled in_tile(const Culled& all) const {
    Culled out;
    out.depth_min = all.depth_min;
    out.depth_max = all.depth_max;
    const Rect region{origin, origin + targets.size};
    for (size_t i = 0; i < all.chunks.size(); ++i) {
      const Rect& r = all.rects[i];
      const Rect cut{glm::max(r.min, region.min), glm::min(r.max, region.max)};
      if (cut.empty()) continue;
      out.chunks.push_back(all.chunks[i]);
      out.screen = out.screen.united(Rect{cut.min - origin, cut.max - origin});
    }
    const Rect& m = all.meshes.screen;
    const Rect mesh_cut{glm::max(m.min, region.min), glm::min(m.max, region.max)};
    if (!all.meshes.visible.empty() && !mesh_cut.empty()) {
      out.meshes.visible = all.meshes.visible;
      out.meshes.screen = Rect{mesh_cut.min - origin, mesh_cut.max - origin};
      out.meshes.depth_min = all.meshes.depth_min;
      out.meshes.depth_max = all.meshes.depth_max;
    }
    return out;
  }

  void render_segment(const Segment& seg, int index, const Camera& cam, const RenderSettings& s,
                      const Culled& in_frame, RenderResult& result) {
    std::optional<StageTimer> stage(std::in_place, result.stats, "mark_ms", s.stage_timings);
    const Culled visible = in_tile(in_frame);
    const MeshPass& mesh_pass = visible.meshes;
    if (visible.chunks.empty() && mesh_pass.visible.empty()) return;
    const Rect screen = visible.screen.united(mesh_pass.screen);

    // Everything this segment may read or write lies within `work`.
    const CompositeMode mode = CompositeMode(s.composite.get_enum("mode"));
    const int radius = seg.style.inpaint.get_int("radius");
    const Rect work = screen.grown(2 * total_footprint(seg.style.filters) + radius + 1, targets.size);

    const float zero4[4] = {0, 0, 0, 0};
    clear_texture_rect(targets.raster_color, work, zero4, GL_RGBA, GL_FLOAT);
    clear_texture_rect(targets.raster_depth, work, &kInf, GL_RED, GL_FLOAT);
    targets.clear_rows(targets.depth_keys, work, targets.int64 ? 8 : 4);
    if (!targets.int64) targets.clear_rows(targets.keys, work, 4);

    // Each pixel's point's spacing for the gap fill, where the segment's
    // clouds have one (none streamed, as segment_sampling); 0 elsewhere (a
    // mesh's pixels).
    const bool pixel_spacing = seg.style.fills_gaps() && !streams(seg);
    if (pixel_spacing) clear_texture_rect(targets.spacing_image(), work, zero4, GL_RED, GL_FLOAT);

    MarkContext mark;
    mark.shaders = &shaders;
    mark.images = &images;
    mark.camera = &cam;
    mark.targets = mark_targets();
    if (pixel_spacing) {
      mark.targets.spacing = &targets.raster_spacing;
      mark.targets.spacing_fbo = targets.spacing_fbo.id();
    }
    mark.chunks = visible.chunks;
    mark.clip = screen;
    mark.frame_chunks = in_frame.chunks;
    mark.frame_clip = in_frame.screen;
    mark.frame_cache = &in_frame.mark_cache;
    mark.depth_min = visible.depth_min;
    mark.depth_max = std::max(visible.depth_max, visible.depth_min);
    mark.time = s.time;
    mark.segment_seed = uint32_t(index) * 2654435761u;
    mark.native = s.native;
    mark.host = &host;
    mark.memory_budget = s.memory_budget > 0 ? s.memory_budget : kDefaultMemoryBudget;
    mark.stats = &result.stats;
    mark.warnings = &result.warnings;
    mark.capture = s.capture_marks ? &result.marks : nullptr;
    std::optional<Rect> mark_coverage;  // set by marks that know it (native points)
    if (!visible.chunks.empty()) {
      mark.clip = visible.screen;
      mark.coverage = &mark_coverage;
      seg.style.mark.mark->draw(mark, seg.style.mark.params);
      mark.coverage = nullptr;
      gl::check_gl(("mark " + seg.style.mark.info->schema.id).c_str());
    }
    if (!mesh_pass.visible.empty()) {
      // After the point mark: the surfaces test their depth against its points.
      MarkContext surface = mark;
      surface.chunks = {};
      surface.meshes = mesh_pass.visible;
      surface.clip = mesh_pass.screen;
      surface.frame_chunks = {};
      surface.frame_cache = nullptr;
      surface.depth_min = mesh_pass.depth_min;
      surface.depth_max = std::max(mesh_pass.depth_max, mesh_pass.depth_min);
      seg.style.surface.mark->draw(surface, seg.style.surface.params);
      gl::check_gl("mark mesh_surface");
    }
    // Where GL drew (or the mark did not say), a pass over the depth finds it.
    const Rect covered = mark_coverage && mesh_pass.visible.empty() ? *mark_coverage : coverage_bounds(screen);
    stage.reset();
    if (covered.empty()) return;

    stage.emplace(result.stats, "filters_ms", s.stage_timings);
    const gl::Texture* current = &targets.raster_color;
    Rect rect = covered;
    if (!seg.style.filters.empty()) {
      clear_texture_rect(targets.color_a, work, zero4, GL_RGBA, GL_FLOAT);
      clear_texture_rect(targets.color_b, work, zero4, GL_RGBA, GL_FLOAT);
      glCopyImageSubData(targets.raster_color.id(), GL_TEXTURE_2D, 0, screen.min.x, screen.min.y, 0,
                         targets.color_a.id(), GL_TEXTURE_2D, 0, screen.min.x, screen.min.y, 0, screen.size().x,
                         screen.size().y, 1);
      gl::check_gl("copy to the filter chain");
      FilterChainImages chain;
      chain.shaders = &shaders;
      chain.images = &images;
      chain.first = &targets.color_a;
      chain.second = &targets.color_b;
      chain.raster_depth = &targets.raster_depth;
      chain.scratch = [this](int i) -> const gl::Texture& { return targets.filter_scratch(i); };
      chain.image_size = targets.size;
      chain.time = s.time;
      chain.segment_seed = mark.segment_seed;
      chain.surface = make_surface_frame(cam, frame, surface_anchor(seg));
      chain.sampling = segment_sampling(seg, in_frame.chunks, in_frame.depth_min);
      chain.fill_gaps = seg.style.mark.info->schema.id == "points";
      chain.raster_spacing = mark.targets.spacing;
      chain.gap_image = [this]() -> const gl::Texture& { return targets.gap_fill_image(); };
      chain.gap_depth_image = [this]() -> const gl::Texture& { return targets.gap_depth_image(); };
      current = run_filter_chain(seg.style.filters, chain, rect);
    }

    stage.emplace(result.stats, "inpaint_ms", s.stage_timings);
    const gl::Texture& depth = mode == CompositeMode::Inpaint
                                   ? inpaint_depth_stage(shaders, targets, seg.style.inpaint, *current, rect)
                                   : targets.raster_depth;
    stage.emplace(result.stats, "composite_ms", s.stage_timings);
    composite_stage(shaders, targets, mode, index, *current, depth, rect);
  }

  // The tile's interior into the frame's buffers, in bands of rows that
  // keep each read under GLsizei's 2 GB.
  void read_tile(const Tile& tile, RenderResult& result) {
    auto t0 = Clock::now();
    const glm::ivec2 at = tile.interior.min - origin, size = tile.interior.size();
    const size_t row_bytes = size_t(frame.x) * 16;
    const int band = int(std::max<size_t>(1, (size_t(1) << 30) / row_bytes));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ROW_LENGTH, frame.x);
    for (int y = 0; y < size.y; y += band) {
      const int rows = std::min(band, size.y - y);
      const size_t first = size_t(tile.interior.min.y + y) * size_t(frame.x) + size_t(tile.interior.min.x);
      const size_t span = size_t(rows - 1) * size_t(frame.x) + size_t(size.x);  // pixels the read touches
      glGetTextureSubImage(targets.accum.id(), 0, at.x, at.y + y, 0, size.x, rows, 1, GL_RGBA, GL_FLOAT,
                           GLsizei(span * 16), result.color.data() + first * 4);
      glGetTextureSubImage(targets.accum_depth.id(), 0, at.x, at.y + y, 0, size.x, rows, 1, GL_RED, GL_FLOAT,
                           GLsizei(span * 4), result.depth.data() + first);
      glGetTextureSubImage(targets.accum_index.id(), 0, at.x, at.y + y, 0, size.x, rows, 1, GL_RED_INTEGER, GL_INT,
                           GLsizei(span * 4), result.segment_index.data() + first);
    }
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl::check_gl("read back");
    result.stats["readback_ms"] += ms_since(t0);
  }

  void finish(const RenderSettings& s, RenderResult& result) {
    auto t0 = Clock::now();
    // Kept for the next frame within the memory budget, else given back.
    if (host.bytes() > (s.memory_budget > 0 ? s.memory_budget : kDefaultMemoryBudget)) host.release();
    result.stats["host_kept_mb"] = double(host.bytes()) / double(1 << 20);
    frame_warnings.report(result.warnings);
    pixel_origin() = glm::ivec2(0);
    origin = glm::ivec2(0);
    const size_t pixels = size_t(s.width) * size_t(s.height);
    // Background under the premultiplied image, and Blender's empty depth.
    const glm::vec4 bg(glm::vec3(s.background) * float(s.background.a), float(s.background.a));
    for (size_t i = 0; i < pixels; ++i) {
      float* c = &result.color[4 * i];
      const float t = 1.0f - c[3];
      for (int k = 0; k < 4; ++k) c[k] += t * bg[k];
      if (!(result.depth[i] < kBackgroundDepth)) result.depth[i] = kBackgroundDepth;
    }
    result.stats["readback_ms"] += ms_since(t0);
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) { gl::Device::instance(); }

Renderer::~Renderer() {
  // GL objects must die on the GL thread; after a shutdown the context and
  // its objects are gone already.
  if (!gl::Device::exists()) {
    (void)impl_.release();
    return;
  }
  try {
    // The trim after every member is gone: the frame targets, buffers and
    // caches are freed after the host scratch's own trim.
    gl::Device::instance().run([this] {
      impl_.reset();
      return_freed_pages();
    });
  } catch (...) {
    (void)impl_.release();  // no context left: leaking beats crashing the host
  }
}

// The frame's tiles: grown by the widest reach of any segment (its mark's
// extent and screen passes, twice its filters' footprints as the segment's
// work area, its inpainting radius); drawn whole when a mark cannot tile.
TilePlan plan_frame_tiles(const Scene& scene, const RenderSettings& s, std::vector<std::string>& warnings) {
  const glm::ivec2 frame{s.width, s.height};
  const int max_image = gl::Device::instance().info().max_texture_size;
  const size_t budget = s.memory_budget > 0 ? s.memory_budget : kDefaultMemoryBudget;
  int halo = 0;
  std::string whole;  // a mark that cannot draw tiles
  for (const Segment& seg : scene.segments) {
    const MarkStep& m = seg.style.mark;
    // The gap fill (points mark, before a filter that reads neighbourhoods)
    // reads up to its reach around a gap pixel (render/filter_chain.h).
    const bool gap_fill = seg.style.fills_gaps();
    const int reach = int(std::ceil(m.mark->extent(m.params).pixels)) + m.mark->screen_reach(m.params) +
                      (gap_fill ? kGapReachMax + kGapPushReach : 0) + total_footprint(seg.style.filters) +
                      seg.style.inpaint.get_int("radius") + 1;
    halo = std::max(halo, reach);
    if (!m.mark->draws_tiles(m.params) && whole.empty()) whole = m.info->schema.id;
    const MarkStep& surface = seg.style.surface;
    if (whole.empty() && mesh_mode(surface.params) == MeshMode::Surface && !surface.mark->draws_tiles(surface.params))
      for (const Instance& inst : seg.instances)
        if (inst.mesh && inst.mesh->num_triangles() > 0) whole = surface.info->schema.id;
  }
  // Captured marks are listed once per frame, so such frames are drawn whole too.
  if (!whole.empty() || s.capture_marks) {
    if (s.width > max_image || s.height > max_image)
      throw GLError("the '" + (whole.empty() ? std::string("capture_marks") : whole) +
                    "' mark draws frames whole, and " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                    " exceeds the GL limit of " + std::to_string(max_image) + " pixels per side");
    const double bytes = double(s.width) * double(s.height) * double(kBytesPerTilePixel);
    if (!whole.empty() && bytes > double(budget))
      warnings.push_back("the '" + whole + "' mark does not draw in tiles yet: the frame is drawn whole (about " +
                         std::to_string(int(std::ceil(bytes / double(1 << 30)))) + " GB, over the memory budget of " +
                         std::to_string(double(budget) / double(1 << 30)).substr(0, 4) + " GB)");
    return whole_frame(frame);
  }
  TilePlan plan = plan_tiles(frame, halo, budget, s.tile_size, max_image);
  if (!plan.fits_budget)
    warnings.push_back("memory budget too small for the styles' halo of " + std::to_string(halo) +
                       " pixels: tiles of " + std::to_string(plan.interior.x) + " pixels exceed it");
  return plan;
}

RenderResult Renderer::render(const Scene& input_scene, const Camera& camera, const RenderSettings& s) {
  if (s.width <= 0 || s.height <= 0 || s.width > kMaxFrameSide || s.height > kMaxFrameSide)
    throw ParameterError("render size must be between 1 and " + std::to_string(kMaxFrameSide) +
                         " pixels per side, got " + std::to_string(s.width) + "x" + std::to_string(s.height));
  if (s.tile_size < 0) throw ParameterError("tile_size must be 0 (from the memory budget) or a number of pixels");
  for (double v : {s.background.r, s.background.g, s.background.b, s.background.a})
    if (!std::isfinite(v)) throw ParameterError("background color must be finite");
  if (camera.resolution != glm::ivec2(0) && camera.resolution != glm::ivec2(s.width, s.height))
    throw ParameterError("the camera was made for " + std::to_string(camera.resolution.x) + "x" +
                         std::to_string(camera.resolution.y) + " but the render is " + std::to_string(s.width) + "x" +
                         std::to_string(s.height) + ": give the camera the render size (its aspect depends on it)");
  std::lock_guard frame_lock(render_mutex_);
  // Out-of-core scans: the points this view draws, streamed from their caches.
  Scene streamed;
  const Scene& scene = with_streamed_clouds(input_scene, camera, {s.width, s.height}, streamed, s.point_budget);
  auto& device = gl::Device::instance();
  const auto t0 = Clock::now();
  RenderResult result;
  const TilePlan plan = plan_frame_tiles(scene, s, result.warnings);
  device.run([&] { impl_->begin_frame(s, plan, result); });
  const size_t n = scene.segments.size();
  // Culled once per frame, in frame pixels; each tile draws the chunks that reach it.
  std::vector<Impl::Culled> culled(n);
  device.run([&] {
    for (size_t i = 0; i < n; ++i) culled[i] = impl_->cull_segment(scene.segments[i], camera, result);
    if (s.point_budget > 0) impl_->apply_point_budget(scene, culled, s.point_budget, result);
  });
  const size_t tiles = plan.tiles.size();
  try {
    for (size_t t = 0; t < tiles; ++t) {
      const Tile& tile = plan.tiles[t];
      const std::string where = tiles > 1 ? "tile " + std::to_string(t + 1) + "/" + std::to_string(tiles) + ": " : "";
      device.run([&] { impl_->begin_tile(tile); });
      for (size_t i = 0; i < n; ++i) {
        const double fraction = (double(t) + double(i) / double(std::max<size_t>(n, 1))) / double(tiles);
        if (s.progress && !s.progress(fraction, where + scene.segments[i].name)) throw RenderCancelled();
        device.run([&] { impl_->render_segment(scene.segments[i], int(i), camera, s, culled[i], result); });
      }
      device.run([&] { impl_->read_tile(tile, result); });
    }
  } catch (...) {
    // A cancelled or failed tile leaves no origin behind for filter runs outside a frame.
    try {
      device.run([] { pixel_origin() = glm::ivec2(0); });
    } catch (...) {
    }
    throw;
  }
  if (s.progress && !s.progress(1.0, "compositing")) throw RenderCancelled();
  device.run([&] { impl_->finish(s, result); });
  result.stats["tiles"] = double(tiles);
  result.stats["tile_halo"] = double(plan.halo);
  result.stats["tile_region_width"] = double(plan.region_size.x);
  result.stats["tile_region_height"] = double(plan.region_size.y);
  result.stats["total_ms"] = ms_since(t0);
  return result;
}

size_t Renderer::cached_clouds() const {
  return gl::Device::instance().run([this] { return impl_->clouds.size(); });
}

AttributeSet Renderer::uploaded_attributes(uint64_t cloud_id) const {
  return gl::Device::instance().run([this, cloud_id] {
    AttributeSet set;
    if (const GpuCloud* g = impl_->clouds.find(cloud_id))
      for (const auto& [key, buffer] : g->buffers)
        if (buffer) set.insert(key);
    return set;
  });
}

uint64_t Renderer::upload_count() const {
  return gl::Device::instance().run([this] { return impl_->clouds.uploads(); });
}

size_t Renderer::cached_meshes() const {
  return gl::Device::instance().run([this] { return impl_->meshes.size(); });
}

uint64_t Renderer::mesh_upload_count() const {
  return gl::Device::instance().run([this] { return impl_->meshes.uploads(); });
}

}  // namespace pointnpr
