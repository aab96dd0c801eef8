// The brush_splats mark's blending (b), an A-buffer of the splats near the
// surface: fragments counted per pixel, lists packed by a sequential prefix
// sum, stored, then each list sorted completely by (depth, point id,
// colour) and alpha-blended front to back (the same bytes whatever the
// point order). Its fragments have a memory budget, and a pixel's list a
// length limit: a frame that would exceed either warns and is blended by
// blur (brush_splats.cpp); nothing is allocated beyond them.
#include <algorithm>
#include <cstdio>
#include <string>

#include "gl/device.h"
#include "gl/shaders.h"
#include "marks/brush_splats/gl_passes.h"
#include "render/filter.h"

namespace pointnpr::brush_gl {
namespace {

constexpr size_t kFragmentBytes = 16;  // brush_abuffer.glsl's Fragment
// Longest list a pixel may have: each list is insertion-sorted by one
// invocation, so its length bounds the work of a pixel (a cloud seen from
// far away would otherwise pile every splat into a few pixels).
constexpr uint32_t kMaxListLength = 512;

}  // namespace

bool draw_a_buffer(const MarkContext& ctx, const ParamValues& p, const std::optional<ExactRaster>& raster) {
  const Rect& clip = ctx.clip;
  // Lists over the clip rect only: 12 bytes of counters a pixel of it.
  const glm::ivec2 rect = clip.size();
  const size_t pixels = size_t(rect.x) * size_t(rect.y);
  const uint32_t zero = 0;
  const gl::Buffer counts = gl::make_buffer(pixels * 4, nullptr, 0);
  const gl::Buffer cursors = gl::make_buffer(pixels * 4, nullptr, 0);
  const gl::Buffer offsets = gl::make_buffer(pixels * 4, nullptr, 0);
  const gl::Buffer row_base = gl::make_buffer((size_t(rect.y) + 2) * 4, nullptr, 0);
  glClearNamedBufferData(counts.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glClearNamedBufferData(cursors.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glClearNamedBufferData(row_base.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  auto bind_lists = [&](const gl::Program& g) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, counts.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, cursors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, row_base.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, offsets.id());
    glUniform2i(g.location("u_list_origin"), clip.min.x, clip.min.y);
    glUniform2i(g.location("u_list_size"), rect.x, rect.y);
  };
  const gl::Framebuffer fbo = make_fbo({}, ctx.targets);
  // The splats near the surface, drawn into the lists by `pass`.
  auto draw_near_splats = [&](const char* pass) {
    const MarkRasterState state(ctx.targets, ctx.clip);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    const gl::Program& g = splat_program(ctx, p, pass);
    g.use();
    set_splat_uniforms(g, ctx, p);
    set_raster_viewport(g, raster);
    near_surface_tests(ctx, g, p);
    bind_lists(g);
    draw_all(ctx, g, p);
  };

  // 1. Count the fragments of every pixel.
  draw_near_splats("PASS_COUNT");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  // 2. Where each list starts, and the total.
  for (const char* pass : {"PASS_ROWS", "PASS_TOTAL"}) {
    const gl::Program& scan = ctx.shaders->compute("brush_abuffer_scan.comp", {pass});
    scan.use();
    bind_lists(scan);
    glUniform2i(scan.location("u_rect_min"), clip.min.x, clip.min.y);
    glUniform2i(scan.location("u_rect_max"), clip.max.x, clip.max.y);
    glDispatchCompute(std::string(pass) == "PASS_ROWS" ? GLuint((clip.size().y + 63) / 64) : 1u, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }
  uint32_t total_longest[2] = {0, 0};
  glGetNamedBufferSubData(row_base.id(), GLintptr(size_t(rect.y) * 4), 8, total_longest);
  const uint32_t total = total_longest[0], longest = total_longest[1];
  const double budget_mib = p.get_float("a_buffer_budget");
  const double needed_mib = double(total) * double(kFragmentBytes) / (1024.0 * 1024.0);
  if (ctx.stats) {
    (*ctx.stats)["a_buffer_fragments"] += double(total);
    (*ctx.stats)["a_buffer_longest_list"] = std::max((*ctx.stats)["a_buffer_longest_list"], double(longest));
  }
  if (total == 0xFFFFFFFFu || needed_mib > budget_mib || longest > kMaxListLength) {
    // A frame in tiles counts its lists per tile: said once per frame (for
    // the first tile over the budget; the others blend by blur as well).
    const bool tiled = frame_size(ctx.targets) != ctx.targets.size;
    const char* prefix = longest > kMaxListLength ? "brush_splats: a pixel of the A-buffer" : "brush_splats: the A-buffer";
    const auto said = [&](const std::string& w) { return w.rfind(prefix, 0) == 0; };
    if (ctx.warnings && !(tiled && std::any_of(ctx.warnings->begin(), ctx.warnings->end(), said))) {
      char text[260];
      if (longest > kMaxListLength)
        std::snprintf(text, sizeof(text),
                      "%s has %u fragments, more than the %u it sorts; blended by blur instead%s", prefix,
                      longest, kMaxListLength, tiled ? " (in the tiles where it does)" : "");
      else
        std::snprintf(text, sizeof(text),
                      "%s needs %s%.1f MiB for %s, over its budget of %.1f MiB; blended by blur instead%s", prefix,
                      total == 0xFFFFFFFFu ? "more than " : "", needed_mib, tiled ? "a tile" : "this frame",
                      budget_mib, tiled ? " (in the tiles over it)" : "");
      ctx.warnings->push_back(text);
    }
    return false;
  }
  // 3. Store them, 4. sort and blend each list.
  const gl::Buffer fragments = gl::make_buffer(std::max<size_t>(total, 1) * kFragmentBytes, nullptr, 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, fragments.id());
  draw_near_splats("PASS_STORE");
  gl::check_gl("brush splats A-buffer");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  const gl::Program& resolve = ctx.shaders->compute("brush_abuffer_resolve.comp");
  resolve.use();
  bind_lists(resolve);
  glBindImageTexture(0, ctx.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, ctx.targets.depth->id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  dispatch_rect(resolve, clip);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  return true;
}

}  // namespace pointnpr::brush_gl
