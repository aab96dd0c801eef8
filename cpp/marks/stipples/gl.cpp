// The stipples mark's passes as GL compute dispatches (shaders/stipples.comp,
// one pass per #define): every pass an order-independent integer atomic
// (min, max, add) or a per-texel gather, so the bytes never vary. For GPUs;
// marks/stipples/native.cpp runs the same rules on the CPU.
#include <algorithm>
#include <tuple>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "marks/stipples/stipples.h"

namespace pointnpr {
namespace {

constexpr uint32_t kInfBits = 0x7f800000u;

// Sets the first `count` uints of `b` (scratch buffers may be larger).
void clear_uint(const gl::Buffer& b, size_t count, uint32_t value) {
  glClearNamedBufferSubData(b.id(), GL_R32UI, 0, GLsizeiptr(count * 4), GL_RED_INTEGER, GL_UNSIGNED_INT, &value);
}

void barrier() { glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); }

// Binds a chunk for a point pass; with the resolution queue on, the pass
// takes the first queue_count() points of the chunk's queue order. Returns
// how many points to dispatch.
uint32_t bind_queued_chunk(const gl::Program& prog, const VisibleChunk& v, const StippleSetup& s) {
  const ParamValues& p = *s.params;
  bind_chunk(prog, v, ColorSource::Constant,
             {{6, v.gpu->find({AttributeKind::PointId})},
              {1, v.gpu->find({AttributeKind::LocalResolution, kStippleSpacingNeighbors})},
              {2, v.gpu->find({AttributeKind::Normal, kStippleNormalNeighbors})}});
  if (s.reads_spacing() && !v.gpu->find({AttributeKind::LocalResolution, kStippleSpacingNeighbors}))
    throw GLError("stipples: the points' spacing was not uploaded");
  if (s.u.level_from_spacing) glUniform1f(prog.location("u_spacing_cell_scale"), spacing_cell_scale(s, v));
  if (s.u.spread_max > 0) {
    glUniform1f(prog.location("u_spread_scale"), spread_scale(s, v));
    glUniform1f(prog.location("u_spread_cap"), spread_cap(v));
  }
  if (s.u.lit_share && !v.gpu->find({AttributeKind::Normal, kStippleNormalNeighbors}))
    throw GLError("stipples: the points' normals were not uploaded");
  const bool queued = draws_queue(v, p);
  glUniform1i(prog.location("u_queue"), queued ? 1 : 0);
  if (!queued) return v.chunk->count;
  const gl::Buffer* order = v.gpu->find({AttributeKind::QueueOrder});
  if (!order) throw GLError("stipples: the queue order was not uploaded");
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 15, order->id());
  const uint32_t count = queue_count(v, p);
  glUniform1ui(prog.location("u_count"), count);
  return count;
}

size_t histogram_bins(const StippleSetup& s) { return s.u.specular ? kStippleHistogramBins : 1; }

class GlStipplePasses final : public StipplePasses {
 public:
  GlStipplePasses(const MarkContext& ctx, const StippleSetup& s)
      : ctx_(ctx),
        s_(s),
        quad_(gl::make_buffer(s.quad_n() * 4, nullptr, GL_DYNAMIC_STORAGE_BIT)),
        light_count_(gl::make_buffer(s.light_n() * 4, nullptr, GL_DYNAMIC_STORAGE_BIT)),
        // The four counts, then the specular histogram (shaders/stipples.comp's Globals).
        globals_(gl::make_buffer(16 + histogram_bins(s) * 4, nullptr, GL_DYNAMIC_STORAGE_BIT)),
        none_(gl::make_buffer(4, nullptr, 0)),
        settings_(gl::make_buffer(sizeof(s.u), &s.u)),
        window_settings_(gl::make_buffer(sizeof(StippleWindow{}.k), nullptr, GL_DYNAMIC_STORAGE_BIT)) {
    step_ = s.u.offset;
    const size_t clip_pixels = size_t(s.clip.size().x) * size_t(s.clip.size().y);
    dot_cov_ = &ctx.targets.scratch_buffer(clip_pixels * 4, 2);
    dot_depth_ = &ctx.targets.scratch_buffer(clip_pixels * 4, 3);
    uint32_t largest = 1;
    for (const VisibleChunk& v : ctx.chunks) largest = std::max(largest, v.chunk->count);
    capture_ = gl::make_buffer(s.u.capture ? size_t(largest) * 16 : 16, nullptr, 0);
    clear_uint(quad_, s.quad_n(), 0xffffffffu);
    clear_uint(light_count_, s.light_n(), 0);
    clear_uint(*dot_cov_, clip_pixels, 0);
    clear_uint(*dot_depth_, clip_pixels, kInfBits);
    clear_uint(globals_, 4 + histogram_bins(s), 0);
    hp_ = hp_other_ = eye_count_ = eye_cover_ = surface_ = &none_;
  }

  void project_casters(std::span<const VisibleChunk> chunks) override {
    const StippleWindow nothing;  // every caster into the quadtree, nothing into a fine texture
    win_ = &nothing;
    hp_ = hp_other_ = eye_count_ = eye_cover_ = &none_;
    project_hp_ = false;
    project_quad_ = true;
    point_pass("PASS_PROJECT", chunks);
    project_quad_ = false;
    win_ = nullptr;
  }

  void hidden_points(const StippleWindow& w, std::span<const VisibleChunk> chunks, bool for_frame, bool casters,
                     bool surface) override {
    window_ = w;
    win_ = &window_;
    const size_t n = w.fine_n();
    const gl::Buffer& hp_a = ctx_.targets.scratch_buffer(n * 4, 0);
    const gl::Buffer& hp_b = ctx_.targets.scratch_buffer(n * 4, 1);
    eye_n_ = s_.counts_eye() ? w.eye_n() : 1;
    eye_count_ = &ctx_.targets.scratch_buffer(eye_n_ * 4, 7);
    eye_cover_ = &ctx_.targets.scratch_buffer(eye_n_ * 4, 8);
    clear_uint(hp_a, n, kInfBits);
    clear_uint(hp_b, n, kInfBits);
    clear_uint(*eye_count_, eye_n_, 0);
    clear_uint(*eye_cover_, eye_n_, 0);
    clear_uint(globals_, 4, 0);
    hp_ = &hp_a;
    hp_other_ = &hp_b;
    project_hp_ = true;
    project_quad_ = casters;
    point_pass("PASS_PROJECT", chunks);
    project_quad_ = false;
    for (int it = 0; it < s_.iterations; ++it) {
      image_pass("PASS_DILATE", w.k.fine_size);
      std::swap(hp_, hp_other_);
    }
    const gl::Buffer& surf_a = ctx_.targets.scratch_buffer(n * 4, 4);
    const gl::Buffer& surf_b = ctx_.targets.scratch_buffer(n * 4, 5);
    clear_uint(surf_a, n, kInfBits);
    const gl::Buffer* spare = hp_other_;
    hp_other_ = &surf_a;
    accumulate_ = for_frame;
    point_pass("PASS_VISIBLE", chunks);
    accumulate_ = false;
    hp_other_ = spare;
    surface_ = &none_;
    if (surface) {
      // The surface's depth for the paper: the visible points spread one
      // texel further (they are fewer than all points), without the step
      // (the nearest visible depth).
      const gl::Buffer* keep_hp = hp_;
      hp_ = &surf_a;
      hp_other_ = &surf_b;
      step_ = 0.0f;
      for (int it = 0; it < s_.iterations + 1; ++it) {
        image_pass("PASS_DILATE", w.k.fine_size);
        std::swap(hp_, hp_other_);
      }
      step_ = s_.u.offset;
      surface_ = hp_;
      hp_ = keep_hp;
      hp_other_ = spare;
    }
  }

  // The covered area per eye cell: the hidden-point texture closed (its
  // spreading undone at the silhouette by as many erosions). Leaves hp as
  // the spread depth.
  void cover() override {
    const gl::Buffer& mask = ctx_.targets.scratch_buffer(window_.fine_n() * 4, 6);
    const gl::Buffer* dilated = hp_;
    const gl::Buffer* spare = hp_other_;
    const gl::Buffer* masks[2] = {&mask, hp_other_};  // hp_other: free once the spreading is done
    for (int it = 0; it < s_.iterations; ++it) {
      hp_other_ = masks[it % 2];
      image_pass("PASS_ERODE", window_.k.fine_size);
      hp_ = hp_other_;
    }
    image_pass("PASS_COVER", window_.k.fine_size);
    hp_ = dilated;
    hp_other_ = spare;
  }

  void reduce_quadtree() override {
    const gl::Program& reduce = ctx_.shaders->compute("stipples.comp", {"PASS_REDUCE"});
    for (int l = s_.u.levels - 1; l >= 0; --l) {
      set_uniforms(reduce);
      bind_all();
      glUniform1i(reduce.location("u_reduce_level"), l);
      const GLuint groups = GLuint(((1 << l) + 15) / 16);
      glDispatchCompute(groups, groups, 1);
      barrier();
    }
  }

  void specular_histogram(std::span<const VisibleChunk> chunks) override { point_pass("PASS_SPECULAR", chunks); }

  std::vector<uint32_t> histogram() override {
    std::vector<uint32_t> hist(kStippleHistogramBins);
    glGetNamedBufferSubData(globals_.id(), 16, GLsizeiptr(kStippleHistogramBins * 4), hist.data());
    return hist;
  }

  void save(StippleFrameState& state) override {
    state.quad.resize(s_.quad_n());
    glGetNamedBufferSubData(quad_.id(), 0, GLsizeiptr(s_.quad_n() * 4), state.quad.data());
    state.light_count.resize(s_.light_n());
    glGetNamedBufferSubData(light_count_.id(), 0, GLsizeiptr(s_.light_n() * 4), state.light_count.data());
  }

  void load(const StippleFrameState& state) override {
    glNamedBufferSubData(quad_.id(), 0, GLsizeiptr(s_.quad_n() * 4), state.quad.data());
    glNamedBufferSubData(light_count_.id(), 0, GLsizeiptr(s_.light_n() * 4), state.light_count.data());
  }

  uint32_t visible() override {
    uint32_t v = 0;
    glGetNamedBufferSubData(globals_.id(), 4, 4, &v);
    return v;
  }

  uint32_t draw_dots(std::span<const VisibleChunk> chunks, float spec_ref,
                     std::vector<CapturedMark>* capture) override {
    // Captured dots are read back per chunk, so the capture buffer stays
    // the size of the largest chunk.
    spec_ref_ = spec_ref;
    const gl::Program& prog = ctx_.shaders->compute("stipples.comp", {"PASS_DRAW"});
    set_uniforms(prog);
    bind_all();
    glUniform1i(prog.location("u_opacity_draws"), s_.opacity_draws ? 1 : 0);
    for (const VisibleChunk& v : chunks) {
      const uint32_t count = bind_queued_chunk(prog, v, s_);
      if (s_.opacity_draws) {
        const gl::Buffer* opacity = v.gpu->find({AttributeKind::SplatOpacity});
        if (!opacity) throw GLError("stipples: the splat opacities were not uploaded");
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 14, opacity->id());
      }
      if (count > 0) glDispatchCompute((count + 127) / 128, 1, 1);
      barrier();
      if (capture) {
        uint32_t g[4] = {0, 0, 0, 0};
        glGetNamedBufferSubData(globals_.id(), 0, 16, g);
        std::vector<glm::vec4> rec(g[3]);
        if (g[3]) glGetNamedBufferSubData(capture_.id(), 0, GLsizeiptr(size_t(g[3]) * 16), rec.data());
        for (const glm::vec4& r : rec) capture->push_back(captured_dot(s_, glm::vec3(r), glm::floatBitsToUint(r.w)));
        const uint32_t zero = 0;
        glNamedBufferSubData(globals_.id(), 12, 4, &zero);
      }
    }
    uint32_t kept = 0;
    glGetNamedBufferSubData(globals_.id(), 8, 4, &kept);
    return kept;
  }

  // Dots over paper into the segment's colour and depth.
  void resolve() override {
    win_ = &window_;
    const gl::Program& prog = ctx_.shaders->compute("stipples.comp", {"PASS_RESOLVE"});
    set_uniforms(prog);
    hp_other_ = surface_;
    bind_all();
    glBindImageTexture(0, ctx_.targets.color->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(1, ctx_.targets.depth->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    dispatch_rect(prog, s_.clip);
  }

 private:
  // The settings blocks (the window's as it is now) and the pass's uniforms.
  void set_uniforms(const gl::Program& prog) const {
    const StippleWindow& w = win_ ? *win_ : window_;
    prog.use();
    for (const auto& [name, bytes, binding] : {std::tuple{"StippleSettings", sizeof(s_.u), 0u},
                                               std::tuple{"StippleWindowSettings", sizeof(w.k), 1u}})
      if (glGetUniformBlockIndex(prog.id(), name) != GL_INVALID_INDEX) gl::check_uniform_block(prog, name, bytes, binding);
    glNamedBufferSubData(window_settings_.id(), 0, sizeof(w.k), &w.k);
    glBindBufferBase(GL_UNIFORM_BUFFER, 0, settings_.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, window_settings_.id());
    glUniform1i(prog.location("u_project_hp"), project_hp_ ? 1 : 0);
    glUniform1i(prog.location("u_project_quad"), project_quad_ ? 1 : 0);
    glUniform1i(prog.location("u_accumulate"), accumulate_ ? 1 : 0);
    glUniform1f(prog.location("u_step"), step_);
    glUniform1f(prog.location("u_spec_ref"), spec_ref_);
  }

  void bind_all() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, hp_->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, hp_other_->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, quad_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, eye_count_->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, eye_cover_->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, light_count_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, dot_cov_->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, dot_depth_->id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 12, globals_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, capture_.id());
  }

  void point_pass(const char* pass, std::span<const VisibleChunk> chunks) {
    const gl::Program& prog = ctx_.shaders->compute("stipples.comp", {pass});
    set_uniforms(prog);
    bind_all();
    // Chunks of one pass touch the buffers only through atomics or reads of
    // earlier passes: one barrier after the pass.
    for (const VisibleChunk& v : chunks) {
      const uint32_t count = bind_queued_chunk(prog, v, s_);
      if (count > 0) glDispatchCompute((count + 127) / 128, 1, 1);
    }
    barrier();
  }

  void image_pass(const char* pass, glm::ivec2 size) {
    const gl::Program& prog = ctx_.shaders->compute("stipples.comp", {pass});
    set_uniforms(prog);
    bind_all();
    glDispatchCompute(GLuint((size.x + 15) / 16), GLuint((size.y + 15) / 16), 1);
    barrier();
  }

  const MarkContext& ctx_;
  const StippleSetup& s_;
  gl::Buffer quad_, light_count_, globals_, none_, settings_, window_settings_, capture_;
  const gl::Buffer* dot_cov_ = nullptr;
  const gl::Buffer* dot_depth_ = nullptr;
  // The window the passes run over (null: the last hidden_points' window),
  // and what its point passes do.
  const StippleWindow* win_ = nullptr;
  StippleWindow window_;
  bool project_hp_ = true, project_quad_ = false, accumulate_ = false;
  size_t eye_n_ = 1;
  const gl::Buffer* hp_;
  const gl::Buffer* hp_other_;
  const gl::Buffer* eye_count_;
  const gl::Buffer* eye_cover_;
  const gl::Buffer* surface_;
  float spec_ref_ = 1.0f;
  float step_ = 0.0f;  // PASS_DILATE's depth per step
};

}  // namespace

std::unique_ptr<StipplePasses> make_gl_stipple_passes(const MarkContext& ctx, const StippleSetup& s) {
  return std::make_unique<GlStipplePasses>(ctx, s);
}

}  // namespace pointnpr
