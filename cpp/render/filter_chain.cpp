#include "render/filter_chain.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "gl/device.h"
#include "render/surface_slope.h"

namespace pointnpr {

FilterStep make_filter_step(const std::string& id, const std::map<std::string, std::vector<double>>& params,
                            const std::map<std::string, std::string>& paths) {
  const FilterInfo& info = find_filter(id);
  FilterStep step;
  step.info = &info;
  step.params = validate(info.schema, params, paths);
  step.filter = info.create();
  return step;
}

int total_footprint(const std::vector<FilterStep>& steps) {
  int total = 0;
  for (const FilterStep& f : steps) total += f.filter->footprint(f.params);
  return total;
}

int gap_fill_reach(const ScanSampling& sampling, const SurfaceFrame& surface) {
  if (!(sampling.spacing > 0.0f)) return kGapSplatReach;
  // Gaps up to twice the spacing close (the shader's u_span); on one side
  // of a gap pixel its end lies at most that far less a pixel away, most
  // pixels where the segment is nearest.
  const float pixel = std::abs(surface.x0.x + sampling.depth_min * surface.x1.x);
  const float span_px = pixel > 0.0f ? 2.0f * sampling.spacing / pixel : float(kGapReachMax);
  return std::clamp(int(std::ceil(span_px)) - 1, kGapSplatReach, kGapReachMax);
}

namespace {

void run_step(const FilterStep& f, const FilterChainImages& in, const gl::Texture& input, const gl::Texture& output,
              const Rect& rect) {
  FilterContext ctx;
  ctx.shaders = in.shaders;
  ctx.images = in.images;
  ctx.input = &input;
  ctx.output = &output;
  ctx.raster_depth = in.raster_depth;
  ctx.scratch = in.scratch;
  ctx.rect = rect;
  ctx.image_size = in.image_size;
  ctx.time = in.time;
  ctx.segment_seed = in.segment_seed;
  ctx.surface = in.surface;
  ctx.sampling = in.sampling;
  f.filter->apply(ctx, f.params);
  gl::check_gl(("filter " + f.info->schema.id).c_str());
}

// The gap fill's lists of pixels to search (gap_fill.comp's, then
// gap_fill_pyramid.comp's, in turn): 3 uints of indirect dispatch
// arguments, the list's length, then a uint per pixel. One buffer, kept for
// the GL context's life (like the shader library) and grown as frames need;
// returned empty and bound to storage binding 3 for `pixels` at most.
const gl::Buffer& empty_pixel_list(size_t pixels) {
  static gl::Buffer* list = new gl::Buffer();
  static size_t list_bytes = 0;
  const size_t bytes = 16 + 4 * pixels;
  if (bytes > list_bytes) {
    *list = gl::make_buffer(bytes, nullptr);
    list_bytes = bytes;
  }
  const GLuint args[4] = {0, 1, 1, 0};
  glNamedBufferSubData(list->id(), 0, sizeof(args), args);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, list->id());
  return *list;
}

// The program in use over the pixels `list` holds (its own groups count).
void dispatch_listed(const gl::Buffer& list) {
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, list.id());
  glDispatchComputeIndirect(0);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
}

// The gap fill's second stage (shaders/gap_fill_pyramid.comp): gaps among
// lone splats, which no line meets on both sides, closed from cells of 2 to
// 2^kGapLevels px pooled from `image` and `depth` (the line fill's), in
// place over `write`. Its atlases are kept like the line fill's buffers below.
void fill_among_lone_splats(const FilterChainImages& images, const gl::Texture& image, const gl::Texture& depth,
                            const Rect& covered, const Rect& write) {
  if (covered.empty() || write.empty()) return;
  // Per cell: colour sum; count, depth sum, centroid sums; nearest depth,
  // spacing and the squares' summary (the shader's u_sum, u_stats, u_front).
  static GLuint atlas[3] = {0, 0, 0};
  static glm::ivec2 atlas_size{0, 0};
  int level_x[kGapLevels];
  glm::ivec2 need{0, (images.image_size.y >> 1) + 4};
  for (int level = 1; level <= kGapLevels; ++level) {
    level_x[level - 1] = need.x;
    need.x += (images.image_size.x >> level) + 4;  // the frame's cells, and one to spare either side
  }
  if (glm::any(glm::greaterThan(need, atlas_size))) {
    atlas_size = glm::max(need, atlas_size);
    for (GLuint& texture : atlas) {
      if (texture) glDeleteTextures(1, &texture);
      glCreateTextures(GL_TEXTURE_2D, 1, &texture);
      glTextureStorage2D(texture, 1, GL_RGBA32F, atlas_size.x, atlas_size.y);
    }
  }
  glBindImageTexture(0, image.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(1, depth.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  const gl::Texture& spacing = images.raster_spacing ? *images.raster_spacing : *images.raster_depth;
  glBindImageTexture(2, spacing.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(3, atlas[0], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(4, atlas[1], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(5, atlas[2], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  const glm::ivec2 origin = pixel_origin();
  // Each level's cells over the written pixels, and one either side (the
  // push reads the 3x3 cells about a pixel's own).
  glm::ivec2 cells_min[kGapLevels], cells_max[kGapLevels];
  for (int level = 1; level <= kGapLevels; ++level) {
    const auto cell = [&](glm::ivec2 p) {
      return glm::ivec2(glm::floor(glm::vec2(p + origin) / float(1 << level)));
    };
    cells_min[level - 1] = cell(write.min) - 1;
    cells_max[level - 1] = cell(write.max - 1) + 2;
  }
  auto set_common = [&](const gl::Program& prog) {
    prog.use();
    glUniform1i(prog.location("u_pixel_spacing"), images.raster_spacing ? 1 : 0);
    glUniform1f(prog.location("u_span"), std::max(2.0f * images.sampling.spacing, 0.0f));
    glUniform1f(prog.location("u_grazing"), kSteepestSurfaceSlope);
    glUniform1iv(prog.location("u_level_x"), kGapLevels, level_x);
    glUniform2iv(prog.location("u_cells_min"), kGapLevels, &cells_min[0].x);
    glUniform2iv(prog.location("u_cells_max"), kGapLevels, &cells_max[0].x);
    glUniform2i(prog.location("u_write_min"), write.min.x, write.min.y);
    glUniform2i(prog.location("u_write_max"), write.max.x, write.max.y);
    glUniform2i(prog.location("u_cover_min"), covered.min.x, covered.min.y);
    glUniform2i(prog.location("u_cover_max"), covered.max.x, covered.max.y);
    set_surface_uniforms(prog, images.surface);
  };
  const std::string levels = "GAP_LEVELS " + std::to_string(kGapLevels);
  for (int level = 1; level <= kGapLevels; ++level) {
    const gl::Program& pull = images.shaders->compute(
        "gap_fill_pyramid.comp", level == 1 ? std::vector<std::string>{"PASS_PULL", "PULL_PIXELS", levels}
                                            : std::vector<std::string>{"PASS_PULL", levels});
    set_common(pull);
    glUniform1i(pull.location("u_level"), level);
    dispatch_rect(pull, Rect{cells_min[level - 1], cells_max[level - 1]});
  }
  const gl::Program& near = images.shaders->compute("gap_fill_pyramid.comp", {"PASS_NEAR", levels});
  set_common(near);
  for (int level = 1; level <= kGapLevels; ++level) {
    glUniform1i(near.location("u_level"), level);
    dispatch_rect(near, Rect{cells_min[level - 1], cells_max[level - 1]});
  }
  // The pixels the push may change, listed, then searched.
  const gl::Buffer& list = empty_pixel_list(size_t(write.size().x) * size_t(write.size().y));
  const gl::Program& classify = images.shaders->compute("gap_fill_pyramid.comp", {"PASS_LIST", levels});
  set_common(classify);
  dispatch_rect(classify, write);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  const gl::Program& push = images.shaders->compute("gap_fill_pyramid.comp", {levels});
  set_common(push);
  glUniform2i(push.location("u_origin"), origin.x, origin.y);
  dispatch_listed(list);
}

// The gap fill (shaders/gap_fill.comp) of the image `in` whose covered
// pixels lie within `covered`, written over `write` of the chain's gap image.
// Returns the filled image, which holds it over `write`: the gap image or
// `pinholes` (the chain's input, `in`, may be it).
const gl::Texture& fill_gaps(const FilterChainImages& images, const gl::Texture& in, const Rect& covered,
                             const Rect& write, const gl::Texture& depth_out, const gl::Texture& pinholes) {
  const gl::Texture& out = images.gap_image();
  // Each 16x16 tile's nearest depth (a float), kept like the pixel list.
  static gl::Buffer* tile_depth = new gl::Buffer();
  static size_t depth_bytes = 0;
  const glm::ivec2 groups = glm::max((write.size() + 15) / 16, glm::ivec2(1));
  const size_t n_tiles = size_t(groups.x) * size_t(groups.y);
  if (4 * n_tiles > depth_bytes) {
    *tile_depth = gl::make_buffer(4 * n_tiles, nullptr);
    depth_bytes = 4 * n_tiles;
  }
  // The sweeps' distances to the nearest covered pixel along the 4 line
  // orientations, a layer each (shaders/gap_fill.comp, PASS_SWEEP); kept
  // like the buffers above.
  static GLuint runs = 0;
  static glm::ivec2 runs_size{0, 0};
  if (glm::any(glm::greaterThan(images.image_size, runs_size))) {
    if (runs) glDeleteTextures(1, &runs);
    runs_size = glm::max(images.image_size, runs_size);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &runs);
    glTextureStorage3D(runs, 1, GL_RG8UI, runs_size.x, runs_size.y, 4);
  }
  glBindImageTexture(5, runs, 0, GL_TRUE, 0, GL_READ_WRITE, GL_RG8UI);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, tile_depth->id());
  const gl::Buffer& work = empty_pixel_list(n_tiles * 256);  // the classify pass lists the search's pixels
  glBindImageTexture(0, in.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
  glBindImageTexture(1, out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(2, images.raster_depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  // Each pixel's spacing (image 6), where the mark wrote it; else the
  // depth, bound but not read (u_pixel_spacing 0).
  const gl::Texture& spacing = images.raster_spacing ? *images.raster_spacing : *images.raster_depth;
  glBindImageTexture(6, spacing.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  glBindImageTexture(7, depth_out.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  if (!covered.empty()) {
    const gl::Program& sweep = images.shaders->compute("gap_fill.comp", {"PASS_SWEEP"});
    sweep.use();
    glUniform2i(sweep.location("u_cover_min"), covered.min.x, covered.min.y);
    glUniform2i(sweep.location("u_cover_max"), covered.max.x, covered.max.y);
    const glm::ivec2 n = covered.size();
    const int lines[4] = {n.y, n.x, n.x + n.y - 1, n.x + n.y - 1};
    for (int o = 0; o < 4; ++o) {
      glUniform1i(sweep.location("u_orientation"), o);
      glDispatchCompute(GLuint((lines[o] + 63) / 64), 1, 1);
    }
  }
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  for (const bool classify : {true, false}) {
    const gl::Program& prog = images.shaders->compute(
        "gap_fill.comp", classify ? std::vector<std::string>{"PASS_CLASSIFY"} : std::vector<std::string>{});
    prog.use();
    // With each pixel's own spacing the search may reach kGapReachMax where
    // the points a pixel's lines meet are sparse enough to ask for it
    // (fill_pixel), and everywhere the segment's reach: its 90th-percentile
    // spacing at its nearest depth alone cut the sparse tenth's own gaps
    // short (slivers between an aerial canopy's lone returns).
    const int reach = gap_fill_reach(images.sampling, images.surface);
    glUniform1i(prog.location("u_reach"), images.raster_spacing ? kGapReachMax : reach);
    glUniform1i(prog.location("u_reach_floor"), reach);
    glUniform1f(prog.location("u_grazing"), kSteepestSurfaceSlope);
    glUniform1f(prog.location("u_span"), std::max(2.0f * images.sampling.spacing, 0.0f));
    glUniform1i(prog.location("u_splat_reach"), kGapSplatReach);
    glUniform1i(prog.location("u_pixel_spacing"), images.raster_spacing ? 1 : 0);
    glUniform2i(prog.location("u_groups"), groups.x, groups.y);
    glUniform2i(prog.location("u_cover_min"), covered.min.x, covered.min.y);
    glUniform2i(prog.location("u_cover_max"), covered.max.x, covered.max.y);
    set_surface_uniforms(prog, images.surface);
    if (classify) {
      dispatch_rect(prog, write);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    } else {
      glUniform2i(prog.location("u_rect_min"), write.min.x, write.min.y);
      glUniform2i(prog.location("u_rect_max"), write.max.x, write.max.y);
      dispatch_listed(work);
    }
  }
  // Gaps among lone splats, where the scan's spacing bounds them.
  if (images.sampling.spacing > 0.0f || images.raster_spacing)
    fill_among_lone_splats(images, out, depth_out, covered, write);
  // Pinholes the lines missed (PASS_SPECK): the fill's colours copied into
  // the other image, closed there; the depths in place. Twice, from one
  // image into the other (`pinholes`: the chain's input, no longer read,
  // and back): pinholes side by side each see the other closed the second
  // time. Within a pixel of the written rect, whose neighbours it reads.
  const Rect inner = write.grown(-1, images.image_size);
  const gl::Texture* from = &out;
  const gl::Texture* to = &pinholes;
  if (!inner.empty()) {
    const gl::Program& speck = images.shaders->compute("gap_fill.comp", {"PASS_SPECK"});
    speck.use();
    glUniform1f(speck.location("u_grazing"), kSteepestSurfaceSlope);
    set_surface_uniforms(speck, images.surface);
    glBindImageTexture(2, depth_out.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    for (int pass = 0; pass < 2; ++pass) {
      glMemoryBarrier(GL_ALL_BARRIER_BITS);  // the last pass's image stores, before the copy reads them
      glCopyImageSubData(from->id(), GL_TEXTURE_2D, 0, write.min.x, write.min.y, 0, to->id(), GL_TEXTURE_2D, 0,
                         write.min.x, write.min.y, 0, write.size().x, write.size().y, 1);
      glBindImageTexture(0, from->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      glBindImageTexture(1, to->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      dispatch_rect(speck, inner);
      std::swap(from, to);
    }
  }
  gl::check_gl("gap fill");
  return *from;
}

}  // namespace

const gl::Texture* run_filter_chain(const std::vector<FilterStep>& steps, const FilterChainImages& in, Rect& rect) {
  const gl::Texture* current = in.first;
  const gl::Texture* other = in.second;
  FilterChainImages chain = in;  // its raster_depth the filled one after the fill
  bool filled = false;
  for (size_t i = 0; i < steps.size(); ++i) {
    const FilterStep& f = steps[i];
    if (!filled && in.fill_gaps && in.gap_image && in.gap_depth_image && f.filter->reads_neighbourhood() &&
        in.raster_depth) {
      // The depths as far as this and the later filters read, where the
      // fill then writes its own.
      const std::vector<FilterStep> rest(steps.begin() + std::ptrdiff_t(i), steps.end());
      const Rect read = rect.grown(2 * total_footprint(rest) + kGapReachMax, in.image_size);
      const gl::Texture& depth = in.gap_depth_image();
      if (!read.empty())
        glCopyImageSubData(in.raster_depth->id(), GL_TEXTURE_2D, 0, read.min.x, read.min.y, 0, depth.id(),
                           GL_TEXTURE_2D, 0, read.min.x, read.min.y, 0, read.size().x, read.size().y, 1);
      // Filled as far as the filter reads: its rect grown by its footprint.
      const int reach = f.filter->footprint(f.params);
      const gl::Texture& gaps = fill_gaps(in, *current, rect, rect.grown(2 * reach, in.image_size), depth, *current);
      filled = true;
      chain.raster_depth = &depth;
      // The filled image stands in for `current`; the filter writes `other`
      // as usual.
      rect = rect.grown(reach, in.image_size);
      run_step(f, chain, gaps, *other, rect);
      std::swap(current, other);
      continue;
    }
    rect = rect.grown(f.filter->footprint(f.params), in.image_size);
    run_step(f, chain, *current, *other, rect);
    std::swap(current, other);
  }
  return current;
}

}  // namespace pointnpr
