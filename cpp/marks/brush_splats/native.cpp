// The brush_splats mark's native path (marks/brush_splats/brush_splats.h):
// the exact (tile-invariant) passes of shaders/brush_splats_tiled.vert/.frag,
// then brush_resolve.comp and brush_blur.comp, on the CPU's threads (TBB),
// for software GL devices, where llvmpipe spends most of the mark's time
// shading the brush's nine Gaussians per fragment, twice.
//
//  1. Setup: every splat (of the chunk's resolution queue when it is on)
//     as brush_common.glsl's brush_splat() and the tiled vertex shader
//     make it: plane, axes, depth range, colour, column angles, and the
//     box of pixels its quad can cover. Batches of splats within half the
//     frame's memory budget,
//     a vector of lanes at a time; the camera-independent part (point
//     frames, native_settings.cpp) kept per cloud between frames.
//  2. Depth pass: each screen bin (render/screen_bins.h) runs its splats
//     nearest first (the minimum does not depend on the order); a
//     fragment's depth comes first (the pixel's ray met with the splat's
//     plane), then the brush of those nearer than the pixel's surface so
//     far or within depth_tolerance radii of it; the nearer ones that cover
//     move the surface. Those within are kept with their brush
//     (Candidates, a run per splat): the surface only comes nearer, so a
//     fragment left behind by more than the tolerance stays so. Once the
//     rest of a bin's splats lie behind its farthest surface, they are
//     dropped.
//  3. Blend: per bin, in point order, the candidates still within the
//     tolerance of the final surface blend: colour sum, transmittance
//     product, as the GL's blending order. A bin with more candidates than
//     their bound, or a frame of several batches, runs the blend as a pass
//     of its own over the splats (the same tests and float operations, so
//     the same bytes).
//  4. Resolve, the rims over the surface behind (native_rims.cpp), blur
//     (with depth occlusion) and upload.
// The brush: exp(-q^lambda / 2) over q / reach (over sqrt(q / reach) for
// lambda < 1, steep at 0) fitted once a frame by eight polynomial pieces,
// or tabulated and interpolated where no piece fits within 1e-5;
// exp(-(qx^l + qy^l) / 2) as the product of the two axes'; within about
// 1e-5 of the shader's, far below the golden images' 2/255. Setup, the
// bins' passes and the blur run Highway's lanes (native_kernels.cpp) with
// the scalar code's float operations in its order, so the bytes never
// depend on the CPU.
#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <memory>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "marks/brush_splats/brush_splats.h"
#include "marks/brush_splats/native_types.h"
#include "render/native_raster.h"
#include "render/screen_bins.h"
#include "scene/gaussian_splats.h"
#include "scene/point_cloud.h"
#include "scene/splat_attributes.h"

namespace pointnpr {
namespace {
using namespace brush_native;

// The host images of the last frames and the workers' scratch, kept by the
// renderer (HostScratch) so a frame does not page-fault them in anew
// (bounded by the largest clip, a tile's region at most).
struct HostImages {
  std::vector<float> surface, accum, reveal, nearest, sums, color, offset;
  std::vector<Splat> splats;  // a batch's (within half the memory budget)
  std::vector<SplatKey> keys;  // theirs
  tbb::enumerable_thread_specific<BinScratch> bins;
  std::atomic<size_t> candidate_capacity{0};  // the workers' largest (Candidates::shared)
  size_t bytes() const {
    size_t n = held_bytes(surface) + held_bytes(accum) + held_bytes(reveal) + held_bytes(nearest) +
               held_bytes(sums) + held_bytes(color) + held_bytes(offset) + held_bytes(splats) + held_bytes(keys);
    for (const BinScratch& b : bins) n += b.bytes();
    return n;
  }
};
HostImages& host_images(HostScratch& host, size_t pixels) {
  HostImages& images = host.get<HostImages>();
  if (images.surface.size() < pixels + 8) {
    images.surface.resize(pixels + kMaxLanes);  // slack for the row loop's last lanes
    images.accum.resize(4 * pixels);
    images.reveal.resize(pixels);
    images.nearest.resize(pixels);
    images.sums.resize(4 * pixels);
    images.color.resize(4 * pixels);
    images.offset.resize(pixels);
  }
  return images;
}

// brush_blur.comp over the clip: along x into `sums` (planar: one plane per
// channel, rgb * w and w), then along y back into `color`, rows in parallel
// (Kernels::blur_x, blur_y).
void blur(const Settings& s, const Kernels& lanes, float* color, const float* depth,
          const std::vector<glm::ivec2>& row_span, float* sums) {
  const glm::ivec2 size = s.clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  float* const planes[4] = {sums, sums + pixels, sums + 2 * pixels, sums + 3 * pixels};
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    lanes.blur_x(s, color, depth, row_span.data(), size, planes, rows.begin(), rows.end());
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    lanes.blur_y(s, color, depth, row_span.data(), size, planes, rows.begin(), rows.end());
  });
}

}  // namespace

void draw_brush_splats_native(const MarkContext& ctx, const ParamValues& p) {
  const Rect clip = ctx.clip;
  if (clip.empty()) {
    if (ctx.coverage) *ctx.coverage = Rect{};
    return;
  }
  const Settings s = resolve_settings(ctx, p);
  const Kernels lanes = kernels(ctx.native.scalar_lanes);
  const int k = p.get_int("resolution_neighbors");
  const int normal_k = p.get_int("normal_neighbors");
  const bool radius_normals = p.get_enum_name("normals") == "radius_3r";
  const ColorSource source = ColorSource(p.get_enum("color_source"));
  const glm::vec4 constant = p.get_color("color");

  // What the point frames follow (the parameters that reach point_frame()).
  std::string frames_key;
  {
    auto add = [&frames_key](auto v) { frames_key += std::to_string(v) + ' '; };
    add(normal_k), add(radius_normals), add(s.resolution_size), add(s.splat_size), add(k), add(s.user_eps);
    for (float f : {s.epsilon, s.world_radius, s.size_scale, s.angle, s.jitter, s.small_cluster, s.elongation_gain,
                    s.max_stretch})
      add(std::bit_cast<uint32_t>(f));
    add(s.tangent_frame), add(s.seed), add(s.two_layers), add(s.clusters), add(p.get_int("cluster_neighbors"));
  }
  // Host data of every chunk, held while drawing. Point frames are kept for
  // clouds of at most kKeptFramesMax points (NativeLimits::kept_frames_max,
  // tests: fewer); larger ones make them per splat, each frame.
  const uint64_t kept_frames_max = NativeLimits::lowered(ctx.native.kept_frames_max, kKeptFramesMax);
  int clouds_with_kept_frames = 0;
  std::vector<Chunk> chunks(ctx.chunks.size());
  std::vector<std::shared_ptr<const void>> held;
  const PointCloud* last = nullptr;
  Chunk proto;
  for (size_t i = 0; i < ctx.chunks.size(); ++i) {
    const VisibleChunk& v = ctx.chunks[i];
    std::shared_ptr<const PointCloud> cloud = chunk_cloud(v, "brush_splats");
    if (cloud.get() != last) {
      last = cloud.get();
      // Their inputs (the caches the GPU cloud's uploads come from).
      auto frame_inputs = [&](std::vector<std::shared_ptr<const void>>& hold) {
        geometry::Analysis& analysis = cloud->analysis();
        FrameInputs in;
        in.ids = cloud->point_index().data();
        if (v.gpu->own_normals) {
          in.normals = cloud->normals().data();
        } else {
          geometry::NormalOptions o{normal_k, geometry::Orientation::Consistent, {}};
          if (radius_normals) o.radius_factor = 3.0;
          auto normals = analysis.normals(o);
          in.normals = normals->data();
          hold.push_back(normals);
        }
        if (s.resolution_size) {
          auto resolution = analysis.surface_resolution(k);
          in.r = resolution->r.data();
          in.eps = resolution->eps.data();
          hold.push_back(resolution);
        }
        if (s.splat_size) {
          auto radii = shared_splat_radii(*cloud, k);
          in.splat_r = radii->data();
          hold.push_back(radii);
        }
        if (s.tangent_frame == 3) {
          // A splat capture's own frame: each splat's longest axis (as the GPU cache uploads it).
          const GaussianSplats* splats = cloud->gaussians();
          auto axes = std::make_shared<const std::vector<glm::vec3>>(
              splats ? splat_axes(*splats, true) : analysis.points().to_original(analysis.pca(normal_k)->major));
          in.axes = axes->data();
          hold.push_back(axes);
        }
        if (s.clusters) {
          auto shapes = analysis.cluster_shapes(p.get_int("cluster_neighbors"));
          in.shapes = shapes.get();
          hold.push_back(shapes);
        }
        return in;
      };
      proto = Chunk{};
      if (cloud->size() <= kept_frames_max) {
        PointFrames& kept = v.gpu->host_slot<PointFrames>("brush_splats point frames");
        const std::string cloud_key = frames_key + std::to_string(v.gpu->own_normals);
        if (kept.key != cloud_key || kept.frames.size() != cloud->size()) {
          kept.key.clear();  // (stale until made)
          std::vector<std::shared_ptr<const void>> inputs;
          const FrameInputs in = frame_inputs(inputs);
          kept.frames.resize(cloud->size());
          PointFrame* frames = kept.frames.data();
          tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(cloud->size()), kGrain),
                            [&](const tbb::blocked_range<uint32_t>& r) {
                              for (uint32_t j = r.begin(); j < r.end(); ++j) frames[j] = point_frame(in, s, j);
                            });
          kept.key = cloud_key;
        }
        proto.frames = kept.frames.data();
        ++clouds_with_kept_frames;
      } else {
        proto.in = frame_inputs(held);
      }
      proto.positions = cloud->local_positions().data();
      proto.colors = host_colors(*v.gpu, *cloud, source, constant);
      proto.shading = lit_by_shading(p, proto.colors.source);
      proto.noise_offset = brush_noise_offset(*cloud, p);
      if (s.opacity_weight) {
        auto opacities = std::make_shared<const std::vector<float>>(splat_opacities(*cloud));
        proto.weight = opacities->data();
        held.push_back(opacities);
      }
      held.push_back(cloud);
    }
    Chunk& c = chunks[i];
    c = proto;
    c.order = draws_queue(v, p) ? v.gpu->host_queue_order().data() + v.chunk->first : nullptr;
    c.first = v.chunk->first;
    c.count = queue_count(v, p);
    c.view = v.view_from_chunk;
  }
  uint64_t drawn = 0;
  for (const Chunk& c : chunks) drawn += c.count;

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const glm::ivec2 size = clip.size();
  const size_t pixels = size_t(size.x) * size_t(size.y);
  HostImages& host = host_images(*ctx.host, pixels);
  const Images im{host.surface.data(), host.accum.data(), host.reveal.data(), host.nearest.data(), size.x, clip.min,
                  host.offset.data()};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(im.surface + r.begin(), im.surface + r.end(), kInf);
    std::fill(im.accum + 4 * r.begin(), im.accum + 4 * r.end(), 0.0f);
    std::fill(im.reveal + r.begin(), im.reveal + r.end(), 1.0f);
    std::fill(im.nearest + r.begin(), im.nearest + r.end(), kInf);
    std::fill(im.offset + r.begin(), im.offset + r.end(), 0.0f);
  });

  // Batches of whole chunks (a chunk larger than a batch is one), set up
  // in parallel and kept in point order; with one batch the blend pass
  // reuses the depth pass's splats.
  using Item = PointItem;
  // A batch's records (a Splat and its key) take at most half the frame's
  // memory budget (the other half: the images and caches), so a cloud of
  // up to 6M drawn splats runs once at the default 2 GiB, and setting up
  // every splat a second time for the blend is rare. NativeLimits::
  // batch_splats (tests): fewer, so that several run the passes apart.
  const uint64_t budget_splats =
      ctx.memory_budget > 0 ? std::max<uint64_t>(kBatchMin, ctx.memory_budget / 2 / (sizeof(Splat) + sizeof(SplatKey)))
                            : kBatch;
  const uint64_t batch_splats = NativeLimits::lowered(ctx.native.batch_splats, budget_splats);
  std::vector<std::pair<size_t, size_t>> batches;
  for (size_t b = 0; b < chunks.size();) {
    size_t e = b;
    uint64_t used = 0;
    while (e < chunks.size() && (e == b || used + chunks[e].count <= batch_splats)) used += chunks[e++].count;
    batches.push_back({b, e});
    b = e;
  }
  std::vector<Splat>& splats = host.splats;
  std::vector<SplatKey>& keys = host.keys;
  double setup_ms = 0.0;
  auto set_up = [&](size_t b, size_t e) {
    const auto ts = Clock::now();
    std::vector<Item> items;
    for (size_t i = b; i < e; ++i) add_point_items(items, uint32_t(i), chunks[i].count);
    // Each point's slot in point order; one not drawn covers nothing.
    std::vector<size_t> slot(items.size() + 1, 0);
    for (size_t n = 0; n < items.size(); ++n) slot[n + 1] = slot[n] + (items[n].end - items[n].begin);
    splats.resize(slot.back());
    keys.resize(slot.back());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t n = r.begin(); n < r.end(); ++n) {
        const Item& it = items[n];
        lanes.set_up(chunks[it.chunk], s, it.begin, it.end, splats.data() + slot[n]);
      }
      for (size_t i = slot[r.begin()]; i < slot[r.end()]; ++i) keys[i] = SplatKey(splats[i]);
    });
    setup_ms += std::chrono::duration<double, std::milli>(Clock::now() - ts).count();
  };
  std::atomic<int> bins_blended_apart{0};  // over Candidates::kMax
  // One pass over the batch in `splats`, bin by bin (Kernels::draw_bin).
  auto pass = [&](Pass which) {
    const BinInputs in{splats.data(), keys.data(), &s, &im};
    auto bounds = [&](size_t i, glm::ivec2& lo, glm::ivec2& hi) {
      lo = keys[i].lo;
      hi = keys[i].hi;
      return lo.x < hi.x && lo.y < hi.y;
    };
    auto bin = [&](const Rect& area, const uint32_t* list, size_t n) {
      BinScratch& scratch = host.bins.local();
      scratch.candidates.shared = &host.candidate_capacity;
      if (lanes.draw_bin(which, in, area, list, n, scratch)) ++bins_blended_apart;
    };
    // Bins of kBinSide (BlockDepths, the rows' arrays): wider ones (past
    // 16384 bins, frames over 67M pixels; NativeLimits::max_bins, tests:
    // past that many) are cut, their lists filtered.
    const size_t max_bins = NativeLimits::lowered(ctx.native.max_bins, 16384);
    for_each_bin_in_order(splats.size(), clip, bounds, [&](const Rect& area, const uint32_t* list, size_t n) {
      if (area.size().x <= kBinSide && area.size().y <= kBinSide) return bin(area, list, n);
      std::vector<uint32_t> part;
      for (int y = area.min.y; y < area.max.y; y += kBinSide)
        for (int x = area.min.x; x < area.max.x; x += kBinSide) {
          const Rect cut{{x, y}, glm::min(glm::ivec2(x, y) + kBinSide, area.max)};
          part.clear();
          for (size_t j = 0; j < n; ++j) {
            const SplatKey& key = keys[list[j]];
            if (key.lo.x < cut.max.x && key.hi.x > cut.min.x && key.lo.y < cut.max.y && key.hi.y > cut.min.y) part.push_back(list[j]);
          }
          bin(cut, part.data(), part.size());
        }
    }, kBinSide, max_bins);
  };
  // One batch: each bin's depth pass keeps the fragments its blend needs.
  // Several: every depth pass, then every blend pass (set up again).
  if (batches.size() == 1) {
    set_up(batches[0].first, batches[0].second);
    pass(Pass::kBoth);
  } else {
    for (const auto& [b, e] : batches) {
      set_up(b, e);
      pass(Pass::kDepth);
    }
  }
  const auto t1 = Clock::now();
  if (batches.size() > 1) {
    for (const auto& [b, e] : batches) {
      set_up(b, e);
      pass(Pass::kBlend);
    }
  }
  const auto t2 = Clock::now();

  // Resolve (brush_resolve.comp): straight colour, coverage, the surface's
  // depth, else (no brush covered half the pixel) the blended splats' own.
  float* color = host.color.data();
  float* depth = im.surface;
  std::vector<glm::ivec2> row_span(size_t(size.y), glm::ivec2(size.x, -1));
  tbb::parallel_for(tbb::blocked_range<int>(0, size.y, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < size.x; ++x) {
        const size_t q = size_t(y) * size_t(size.x) + size_t(x);
        const float alpha = 1.0f - std::clamp(im.reveal[q], 0.0f, 1.0f);
        const float* acc = im.accum + 4 * q;
        float* c = color + 4 * q;
        if (alpha > 0.0f && acc[3] > 0.0f) {
          for (int ch = 0; ch < 3; ++ch) c[ch] = std::clamp(acc[ch] / acc[3], 0.0f, 1.0f);
          c[3] = alpha;
          if (std::isinf(depth[q])) depth[q] = im.nearest[q];
          row_span[size_t(y)] = {std::min(row_span[size_t(y)].x, x), x};
        } else {
          std::fill(c, c + 4, 0.0f);
          depth[q] = kInf;
        }
      }
  });
  fill_rims_native(rim_reach(ctx, p), color, depth, im.offset, size, row_span, host.sums.data());
  if (p.get_enum_name("blending") != "none" && p.get_int("blur_radius") > 0)
    blur(s, lanes, color, depth, row_span, host.sums.data());
  const float* result = color;
  const auto t3 = Clock::now();
  upload_cpu_mark(ctx.targets, clip, result, depth, row_span, ctx.coverage, "brush_splats");
  if (ctx.stats) {
    auto ms = [](Clock::time_point a, Clock::time_point b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    (*ctx.stats)["splats_drawn"] += double(drawn);
    (*ctx.stats)["brush_native_setup_ms"] += setup_ms;
    (*ctx.stats)["brush_native_batches"] += double(batches.size());
    (*ctx.stats)["brush_native_lanes"] = double(lanes.lanes);
    (*ctx.stats)["brush_native_falloff_degree"] = s.pieces ? double(s.degree) : 0.0;  // 0: the table
    (*ctx.stats)["brush_native_clouds_with_kept_frames"] += double(clouds_with_kept_frames);
    (*ctx.stats)["brush_native_bins_blended_apart"] += double(bins_blended_apart.load());
    (*ctx.stats)["brush_native_depth_ms"] += ms(t0, t1);
    (*ctx.stats)["brush_native_blend_ms"] += ms(t1, t2);
    (*ctx.stats)["brush_native_resolve_ms"] += ms(t2, t3);
    (*ctx.stats)["brush_native_upload_ms"] += ms(t3, Clock::now());
  }
}

}  // namespace pointnpr
