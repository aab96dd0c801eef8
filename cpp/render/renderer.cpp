#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <map>

#include "geometry/analysis.h"
#include "gl/device.h"
#include "gl/objects.h"
#include "gl/shaders.h"
#include "render/image_textures.h"

namespace pointnpr {

namespace {
template <class T>
std::vector<T> take(std::vector<std::vector<T>>& list, size_t size) {
  for (auto it = list.begin(); it != list.end(); ++it)
    if (it->size() == size) {
      std::vector<T> v = std::move(*it);
      list.erase(it);
      return v;
    }
  return std::vector<T>(size);
}
template <class T>
void keep(std::vector<std::vector<T>>& list, std::vector<T>&& v) {
  constexpr size_t kMaxKept = 6;  // a few frames' worth, in flight at once
  if (!v.empty() && list.size() < kMaxKept) list.push_back(std::move(v));
}
}  // namespace

std::vector<float> BufferPool::take_floats(size_t size) {
  std::lock_guard lock(mutex_);
  return take(floats_, size);
}
std::vector<int32_t> BufferPool::take_ints(size_t size) {
  std::lock_guard lock(mutex_);
  return take(ints_, size);
}
void BufferPool::give(std::vector<float>&& v) {
  std::lock_guard lock(mutex_);
  keep(floats_, std::move(v));
}
void BufferPool::give(std::vector<int32_t>&& v) {
  std::lock_guard lock(mutex_);
  keep(ints_, std::move(v));
}

RenderResult::~RenderResult() {
  if (!pool) return;
  pool->give(std::move(color));
  pool->give(std::move(depth));
  pool->give(std::move(segment_index));
}

RasterizerKind parse_rasterizer(const std::string& s) {
  if (s == "compute") return RasterizerKind::Compute;
  if (s == "gl_points") return RasterizerKind::GlPoints;
  throw ParameterError("rasterizer must be 'compute' or 'gl_points', got '" + s + "'");
}

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

constexpr float kMaxSplatPixels = 32.0f;
const float kInf = std::numeric_limits<float>::infinity();

// GPU copy of a cloud: positions always, other attributes on demand.
struct GpuCloud {
  std::weak_ptr<const PointCloud> source;
  gl::Buffer positions;
  gl::Buffer colors, intensity, classification;
  // snorm8 x3 per point, by source: 0 the cloud's own, k estimated from k
  // neighbours (styles sharing a cloud may ask for different k).
  std::map<int, gl::Buffer> normals;
  bool own_normals = false;
  gl::VertexArray vao;  // for the GL_POINTS path
  uint32_t uploaded = 0;
  float intensity_scale = 1.0f;
};

// Unit normals as signed 8-bit x, y, z (0.5 degree steps: plenty for
// shading, a quarter of the upload).
std::vector<uint32_t> pack_normals(const std::vector<glm::vec3>& normals) {
  std::vector<uint32_t> out(normals.size());
  for (size_t i = 0; i < normals.size(); ++i) {
    uint32_t packed = 0;
    for (int c = 0; c < 3; ++c) {
      const float v = std::isfinite(normals[i][c]) ? std::clamp(normals[i][c], -1.0f, 1.0f) : 0.0f;
      packed |= uint32_t(uint8_t(int8_t(std::lround(v * 127.0f)))) << (8 * c);
    }
    out[i] = packed;
  }
  return out;
}

// A chunk that survived culling, with its float view transform.
struct VisibleChunk {
  const GpuCloud* gpu;
  const PointChunk* chunk;
  glm::mat4 view_from_chunk;
  uint32_t key_base;
};

struct FrameTargets {
  glm::ivec2 size{0, 0};
  bool int64 = false;
  gl::Buffer depth_keys;  // uint per pixel (or uint64 per pixel with int64 atomics)
  gl::Buffer keys;        // uint per pixel (32-bit path)
  gl::Buffer bbox;        // 4 ints
  gl::Texture raster_color, raster_depth, color_a, color_b, inpainted, accum, accum_depth, accum_index;
  gl::Texture gl_depth;   // depth attachment of the GL_POINTS path
  gl::Framebuffer fbo;
  std::deque<gl::Texture> scratch;  // deque: references stay valid as it grows
};

}  // namespace

struct Renderer::Impl {
  gl::ShaderLibrary shaders;
  ImageTextures images;
  std::shared_ptr<BufferPool> pool = std::make_shared<BufferPool>();
  std::map<uint64_t, GpuCloud> clouds;
  FrameTargets targets;
  uint64_t uploads = 0;

  void collect_garbage() {
    for (auto it = clouds.begin(); it != clouds.end();)
      it = it->second.source.expired() ? clouds.erase(it) : std::next(it);
  }

  template <class T>
  gl::Buffer upload(const std::vector<T>& data) {
    ++uploads;
    return gl::make_buffer(data.size() * sizeof(T), data.data(), 0);
  }

  // normal_k: the neighbours to estimate normals from, where the style
  // shades and the cloud has none of its own.
  GpuCloud& gpu_cloud(const std::shared_ptr<const PointCloud>& cloud, uint32_t needed, int normal_k) {
    GpuCloud& g = clouds[cloud->id()];
    if (!g.positions) {
      g.source = cloud;
      g.own_normals = cloud->has(Attribute::Normal);
      g.positions = upload(cloud->local_positions());
      GLuint vao = 0;
      glCreateVertexArrays(1, &vao);
      g.vao = gl::VertexArray(vao);
      glVertexArrayVertexBuffer(vao, 0, g.positions.id(), 0, sizeof(glm::vec3));
      glEnableVertexArrayAttrib(vao, 0);
      glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(vao, 0, 0);
    }
    const uint32_t missing = needed & ~g.uploaded;
    if ((missing & uint32_t(Attribute::Color)) && cloud->has(Attribute::Color))
      g.colors = upload(cloud->colors());
    if ((missing & uint32_t(Attribute::Intensity)) && cloud->has(Attribute::Intensity)) {
      g.intensity = upload(cloud->intensity());
      float peak = 0.0f;
      for (float v : cloud->intensity()) peak = std::max(peak, v);
      g.intensity_scale = peak > 0.0f ? 1.0f / peak : 1.0f;
    }
    if ((missing & uint32_t(Attribute::Classification)) && cloud->has(Attribute::Classification))
      g.classification = upload(cloud->classification());
    if (needed & uint32_t(Attribute::Normal)) {
      const int source = g.own_normals ? 0 : normal_k;
      if (!g.normals.count(source)) {
        if (source == 0) {
          g.normals[0] = upload(pack_normals(cloud->normals()));
        } else {
          // Estimated once per cloud and k (the cloud's geometry cache keeps
          // them), consistently oriented; the shading is two-sided anyway.
          const auto estimated = cloud->analysis().normals({source, geometry::Orientation::Consistent, {}});
          g.normals[source] = upload(pack_normals(*estimated));
        }
      }
    }
    g.uploaded |= needed;
    gl::check_gl("point upload");
    return g;
  }

  void ensure_targets(glm::ivec2 size, bool int64) {
    if (targets.size == size && targets.int64 == int64) return;
    const int max_size = gl::Device::instance().info().max_texture_size;
    if (size.x > max_size || size.y > max_size)
      throw GLError("image size " + std::to_string(size.x) + "x" + std::to_string(size.y) +
                    " exceeds the GL limit of " + std::to_string(max_size));
    targets = FrameTargets();
    targets.size = size;
    targets.int64 = int64;
    const size_t pixels = size_t(size.x) * size_t(size.y);
    targets.depth_keys = gl::make_buffer(pixels * (int64 ? 8 : 4), nullptr);
    targets.keys = gl::make_buffer(int64 ? 4 : pixels * 4, nullptr);
    targets.bbox = gl::make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    targets.raster_color = gl::Texture(GL_RGBA32F, size);
    targets.raster_depth = gl::Texture(GL_R32F, size);
    targets.color_a = gl::Texture(GL_RGBA32F, size);
    targets.color_b = gl::Texture(GL_RGBA32F, size);
    targets.inpainted = gl::Texture(GL_R32F, size);
    targets.accum = gl::Texture(GL_RGBA32F, size);
    targets.accum_depth = gl::Texture(GL_R32F, size);
    targets.accum_index = gl::Texture(GL_R32I, size);
    targets.gl_depth = gl::Texture(GL_DEPTH_COMPONENT32F, size);
    GLuint fbo = 0;
    glCreateFramebuffers(1, &fbo);
    targets.fbo = gl::Framebuffer(fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, targets.raster_color.id(), 0);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT1, targets.raster_depth.id(), 0);
    glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, targets.gl_depth.id(), 0);
    const GLenum bufs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(fbo, 2, bufs);
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw GLError("the GL_POINTS framebuffer is incomplete");
    gl::check_gl("frame target allocation");
  }

  const gl::Texture& scratch(int index) {
    while (int(targets.scratch.size()) <= index) targets.scratch.emplace_back(GL_RGBA32F, targets.size);
    return targets.scratch[size_t(index)];
  }

  void clear_texture(const gl::Texture& t, const Rect& r, const void* value, GLenum format, GLenum type) {
    if (r.empty()) return;
    glClearTexSubImage(t.id(), 0, r.min.x, r.min.y, 0, r.size().x, r.size().y, 1, format, type, value);
  }

  // Clears whole rows [r.min.y, r.max.y) of a per-pixel buffer: one call.
  void clear_rows(const gl::Buffer& b, const Rect& r, size_t bytes_per_pixel) {
    if (r.empty()) return;
    const size_t first = size_t(r.min.y) * size_t(targets.size.x) * bytes_per_pixel;
    const size_t count = size_t(r.size().y) * size_t(targets.size.x) * bytes_per_pixel;
    const uint32_t ones = 0xffffffffu;
    glClearNamedBufferSubData(b.id(), GL_R32UI, GLintptr(first), GLsizeiptr(count), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &ones);
  }

  void begin_frame(const RenderSettings& s) {
    collect_garbage();
    ensure_targets({s.width, s.height}, gl::Device::instance().info().int64_atomics);
    const Rect all{{0, 0}, targets.size};
    const float zero4[4] = {0, 0, 0, 0};
    const int32_t minus_one = -1;
    clear_texture(targets.accum, all, zero4, GL_RGBA, GL_FLOAT);
    clear_texture(targets.accum_depth, all, &kInf, GL_RED, GL_FLOAT);
    clear_texture(targets.accum_index, all, &minus_one, GL_RED_INTEGER, GL_INT);
    gl::check_gl("frame start");
  }

  // Culls chunks against the view volume (in double) and returns the
  // conservative screen rectangle the survivors can touch.
  std::vector<VisibleChunk> cull(const Segment& seg, const Camera& cam, Rect& screen,
                                 RenderResult& result) {
    std::vector<VisibleChunk> visible;
    const uint32_t needed = seg.style.required_attributes();
    uint32_t key_base = 0;
    int total = 0, culled = 0;
    screen = Rect{};
    const glm::ivec2 size = targets.size;
    const float margin = kMaxSplatPixels * 0.5f + 1.0f;
    for (const Instance& inst : seg.instances) {
      if (!inst.cloud || inst.cloud->size() == 0) continue;
      GpuCloud* gpu = nullptr;
      const glm::dmat4 view_from_object = cam.view_from_world * inst.world_from_object;
      for (const PointChunk& chunk : inst.cloud->chunks()) {
        ++total;
        const glm::dmat4 view_from_chunk = view_from_object * glm::translate(glm::dmat4(1.0), chunk.origin);
        bool all_near = true, all_far = true, crosses_near = false;
        glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        for (int c = 0; c < 8; ++c) {
          const glm::dvec3 corner((c & 1) ? chunk.local_max.x : chunk.local_min.x,
                                  (c & 2) ? chunk.local_max.y : chunk.local_min.y,
                                  (c & 4) ? chunk.local_max.z : chunk.local_min.z);
          const glm::dvec4 v = view_from_chunk * glm::dvec4(corner, 1.0);
          const double dist = -v.z;
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
          r.min = glm::ivec2(glm::max(glm::floor(lo - double(margin)), glm::dvec2(0.0)));
          r.max = glm::ivec2(glm::min(glm::ceil(hi + double(margin)), glm::dvec2(size)));
        }
        if (all_near || all_far || r.empty()) {
          ++culled;
          key_base += chunk.count;
          continue;
        }
        if (!gpu) gpu = &gpu_cloud(inst.cloud, needed, seg.style.rasterize.get_int("normal_neighbors"));
        screen = screen.united(r);
        visible.push_back({gpu, &chunk, glm::mat4(view_from_chunk), key_base});
        key_base += chunk.count;
      }
      const uint32_t color = seg.style.color_attribute();
      if (color && !inst.cloud->has(Attribute(color)))
        result.warnings.push_back("segment '" + seg.name + "': its style colors points by " +
                                  seg.style.rasterize.get_enum_name("color_source") +
                                  " but a cloud has none; the constant color is used");
    }
    result.stats["chunks_total"] += total;
    result.stats["chunks_culled"] += culled;
    return visible;
  }

  void set_raster_uniforms(const gl::Program& p, const Segment& seg, const Camera& cam, const Rect& clip) {
    const ParamValues& r = seg.style.rasterize;
    glUniformMatrix4fv(p.location("u_projection"), 1, GL_FALSE, glm::value_ptr(glm::mat4(cam.projection)));
    glUniform2i(p.location("u_size"), targets.size.x, targets.size.y);
    glUniform1f(p.location("u_near"), float(cam.clip_start));
    glUniform1f(p.location("u_far"), float(cam.clip_end));
    glUniform1i(p.location("u_ortho"), cam.orthographic ? 1 : 0);
    glUniform1i(p.location("u_size_mode"), r.get_enum("size_mode"));
    glUniform1f(p.location("u_point_size"), float(r.get_float("point_size")));
    glUniform1f(p.location("u_world_size"), float(r.get_float("world_size")));
    glUniform1f(p.location("u_px_per_unit"), float(cam.pixels_per_unit(1.0, targets.size.y)));
    glUniform1f(p.location("u_max_size"), kMaxSplatPixels);
    const glm::vec4 c = r.get_color("color");
    glUniform4f(p.location("u_constant_color"), c.r, c.g, c.b, c.a);
    glUniform4i(p.location("u_clip_rect"), clip.min.x, clip.min.y, clip.max.x, clip.max.y);
    // Towards the light, in view space: elevation away from the view axis,
    // azimuth around it (0 from the right, 90 from above).
    const double azimuth = glm::radians(r.get_float("light_azimuth")),
                 elevation = glm::radians(r.get_float("light_elevation"));
    glUniform1i(p.location("u_shading"), seg.style.shaded() ? 1 : 0);
    glUniform1f(p.location("u_shading_strength"), float(r.get_float("shading_strength")));
    glUniform3f(p.location("u_light_dir"), float(std::sin(elevation) * std::cos(azimuth)),
                float(std::sin(elevation) * std::sin(azimuth)), float(std::cos(elevation)));
  }

  // Binds the chunk's cloud buffers and chooses the color source it can serve.
  void bind_cloud(const gl::Program& p, const VisibleChunk& v, const Segment& seg) {
    const GpuCloud& g = *v.gpu;
    int source = seg.style.rasterize.get_enum("color_source");
    const gl::Buffer* attr = nullptr;
    if (source == int(ColorSource::Rgb)) attr = &g.colors;
    if (source == int(ColorSource::Intensity)) attr = &g.intensity;
    if (source == int(ColorSource::Classification)) attr = &g.classification;
    if (attr && !*attr) source = int(ColorSource::Constant);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.positions.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, attr && *attr ? attr->id() : g.positions.id());
    const auto normals = seg.style.shaded()
                             ? g.normals.find(g.own_normals ? 0 : seg.style.rasterize.get_int("normal_neighbors"))
                             : g.normals.end();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, normals != g.normals.end() ? normals->second.id() : g.positions.id());
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_chunk)));
    glUniformMatrix3fv(p.location("u_normal_matrix"), 1, GL_FALSE, glm::value_ptr(normal_matrix));
    glUniform1i(p.location("u_color_source"), source);
    glUniform1f(p.location("u_intensity_scale"), g.intensity_scale);
    glUniformMatrix4fv(p.location("u_view_from_chunk"), 1, GL_FALSE, glm::value_ptr(v.view_from_chunk));
    glUniform1ui(p.location("u_first"), v.chunk->first);
    glUniform1ui(p.location("u_count"), v.chunk->count);
    glUniform1ui(p.location("u_key_base"), v.key_base);
  }

  void rasterize_compute(const Segment& seg, const Camera& cam, const std::vector<VisibleChunk>& chunks,
                         const Rect& clip) {
    const bool int64 = targets.int64;
    std::vector<std::vector<std::string>> passes;
    if (int64) {
      passes = {{"INT64_ATOMICS", "PASS_DEPTH"}, {"INT64_ATOMICS", "PASS_COLOR"}};
    } else {
      passes = {{"PASS_DEPTH"}, {"PASS_KEY"}, {"PASS_COLOR"}};
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, targets.depth_keys.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, targets.keys.id());
    glBindImageTexture(0, targets.raster_color.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(1, targets.raster_depth.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    for (const auto& defines : passes) {
      const gl::Program& p = shaders.compute("raster_points.comp", defines);
      p.use();
      set_raster_uniforms(p, seg, cam, clip);
      for (const VisibleChunk& v : chunks) {
        bind_cloud(p, v, seg);
        glDispatchCompute((v.chunk->count + 127) / 128, 1, 1);
      }
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
  }

  void rasterize_gl_points(const Segment& seg, const Camera& cam, const std::vector<VisibleChunk>& chunks,
                           const Rect& clip) {
    const gl::Program& p = shaders.graphics("raster_points.vert", "raster_points.frag");
    glBindFramebuffer(GL_FRAMEBUFFER, targets.fbo.id());
    glViewport(0, 0, targets.size.x, targets.size.y);
    glEnable(GL_SCISSOR_TEST);
    glScissor(clip.min.x, clip.min.y, clip.size().x, clip.size().y);
    const float zero = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &zero);  // reversed Z: 0 is the far end
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glEnable(GL_PROGRAM_POINT_SIZE);
    p.use();
    set_raster_uniforms(p, seg, cam, clip);
    for (const VisibleChunk& v : chunks) {
      bind_cloud(p, v, seg);
      glBindVertexArray(v.gpu->vao.id());
      glDrawArrays(GL_POINTS, GLint(v.chunk->first), GLsizei(v.chunk->count));
    }
    glBindVertexArray(0);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_SCISSOR_TEST);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
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
    for (const Instance& inst : seg.instances)
      if (inst.cloud && inst.cloud->size() > 0)
        return inst.world_from_object *
               glm::translate(glm::dmat4(1.0), 0.5 * (inst.cloud->bounds_min() + inst.cloud->bounds_max()));
    return glm::dmat4(1.0);
  }

  void render_segment(const Segment& seg, int index, const Camera& cam, const RenderSettings& s,
                      RenderResult& result) {
    auto t0 = Clock::now();
    Rect screen;
    std::vector<VisibleChunk> chunks = cull(seg, cam, screen, result);
    if (chunks.empty()) return;
    size_t points = 0;
    for (const auto& v : chunks) points += v.chunk->count;
    result.stats["points_drawn"] += double(points);

    // Everything this segment may read or write lies within `work`.
    int total_footprint = 0;
    for (const FilterStep& f : seg.style.filters) total_footprint += f.filter->footprint(f.params);
    const CompositeMode mode = CompositeMode(s.composite.get_enum("mode"));
    const int radius = seg.style.inpaint.get_int("radius");
    const Rect work = screen.grown(2 * total_footprint + radius + 1, targets.size);

    const float zero4[4] = {0, 0, 0, 0};
    clear_texture(targets.raster_color, work, zero4, GL_RGBA, GL_FLOAT);
    clear_texture(targets.raster_depth, work, &kInf, GL_RED, GL_FLOAT);
    if (s.rasterizer == RasterizerKind::Compute) {
      clear_rows(targets.depth_keys, work, targets.int64 ? 8 : 4);
      if (!targets.int64) clear_rows(targets.keys, work, 4);
      rasterize_compute(seg, cam, chunks, screen);
    } else {
      rasterize_gl_points(seg, cam, chunks, screen);
    }
    gl::check_gl("rasterization");
    const Rect covered = coverage_bounds(screen);
    glFinish();
    result.stats["rasterize_ms"] += ms_since(t0);
    if (covered.empty()) return;

    // Filter chain: ping-pong between two images, each filter's rect grows
    // by its footprint (cost follows coverage, not the frame size).
    t0 = Clock::now();
    const gl::Texture* current = &targets.raster_color;
    Rect rect = covered;
    if (!seg.style.filters.empty()) {
      clear_texture(targets.color_a, work, zero4, GL_RGBA, GL_FLOAT);
      clear_texture(targets.color_b, work, zero4, GL_RGBA, GL_FLOAT);
      glCopyImageSubData(targets.raster_color.id(), GL_TEXTURE_2D, 0, screen.min.x, screen.min.y, 0,
                         targets.color_a.id(), GL_TEXTURE_2D, 0, screen.min.x, screen.min.y, 0, screen.size().x,
                         screen.size().y, 1);
      gl::check_gl("copy to the filter chain");
      current = &targets.color_a;
      const gl::Texture* other = &targets.color_b;
      const SurfaceFrame surface = make_surface_frame(cam, targets.size, surface_anchor(seg));
      for (const FilterStep& f : seg.style.filters) {
        rect = rect.grown(f.filter->footprint(f.params), targets.size);
        FilterContext ctx;
        ctx.shaders = &shaders;
        ctx.images = &images;
        ctx.input = current;
        ctx.output = other;
        ctx.raster_depth = &targets.raster_depth;
        ctx.scratch = [this](int i) -> const gl::Texture& { return scratch(i); };
        ctx.rect = rect;
        ctx.image_size = targets.size;
        ctx.time = s.time;
        ctx.segment_seed = uint32_t(index) * 2654435761u;
        ctx.surface = surface;
        f.filter->apply(ctx, f.params);
        gl::check_gl(("filter " + f.info->schema.id).c_str());
        std::swap(current, other);
      }
    }
    glFinish();
    result.stats["filters_ms"] += ms_since(t0);

    t0 = Clock::now();
    const gl::Texture* depth = &targets.raster_depth;
    if (mode == CompositeMode::Inpaint) {
      const gl::Program& p = shaders.compute("inpaint_depth.comp");
      p.use();
      glUniform1f(p.location("u_threshold"), float(seg.style.inpaint.get_float("threshold")));
      glUniform1i(p.location("u_radius"), radius);
      glBindImageTexture(0, targets.raster_color.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      glBindImageTexture(1, current->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      glBindImageTexture(2, targets.raster_depth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
      glBindImageTexture(3, targets.inpainted.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
      dispatch_rect(p, rect);
      depth = &targets.inpainted;
    }
    glFinish();
    result.stats["inpaint_ms"] += ms_since(t0);

    t0 = Clock::now();
    const gl::Program& p = shaders.compute("composite.comp");
    p.use();
    glUniform1i(p.location("u_mode"), int(mode));
    glUniform1i(p.location("u_segment"), index);
    glBindImageTexture(0, current->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, depth->id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindImageTexture(2, targets.accum.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(3, targets.accum_depth.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
    glBindImageTexture(4, targets.accum_index.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32I);
    dispatch_rect(p, rect);
    gl::check_gl("compositing");
    glFinish();
    result.stats["composite_ms"] += ms_since(t0);
  }

  void finish(const RenderSettings& s, RenderResult& result) {
    auto t0 = Clock::now();
    const size_t pixels = size_t(s.width) * size_t(s.height);
    result.width = s.width;
    result.height = s.height;
    result.pool = pool;
    result.color = pool->take_floats(pixels * 4);
    result.depth = pool->take_floats(pixels);
    result.segment_index = pool->take_ints(pixels);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(targets.accum.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(pixels * 16), result.color.data());
    glGetTextureImage(targets.accum_depth.id(), 0, GL_RED, GL_FLOAT, GLsizei(pixels * 4), result.depth.data());
    glGetTextureImage(targets.accum_index.id(), 0, GL_RED_INTEGER, GL_INT, GLsizei(pixels * 4),
                      result.segment_index.data());
    gl::check_gl("read back");
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
    gl::Device::instance().run([this] { impl_.reset(); });
  } catch (...) {
    (void)impl_.release();  // no context left: leaking beats crashing the host
  }
}

RenderResult Renderer::render(const Scene& scene, const Camera& camera, const RenderSettings& s) {
  if (s.width <= 0 || s.height <= 0 || s.width > 32768 || s.height > 32768)
    throw ParameterError("render size must be between 1 and 32768 pixels per side, got " + std::to_string(s.width) +
                         "x" + std::to_string(s.height));
  for (double v : {s.background.r, s.background.g, s.background.b, s.background.a})
    if (!std::isfinite(v)) throw ParameterError("background color must be finite");
  std::lock_guard frame_lock(render_mutex_);
  auto& device = gl::Device::instance();
  const auto t0 = Clock::now();
  RenderResult result;
  device.run([&] { impl_->begin_frame(s); });
  const size_t n = scene.segments.size();
  for (size_t i = 0; i < n; ++i) {
    if (s.progress && !s.progress(double(i) / double(std::max<size_t>(n, 1)), scene.segments[i].name))
      throw RenderCancelled();
    device.run([&] { impl_->render_segment(scene.segments[i], int(i), camera, s, result); });
  }
  if (s.progress && !s.progress(1.0, "compositing")) throw RenderCancelled();
  device.run([&] { impl_->finish(s, result); });
  result.stats["total_ms"] = ms_since(t0);
  return result;
}

size_t Renderer::cached_clouds() const {
  return gl::Device::instance().run([this] { return impl_->clouds.size(); });
}

uint32_t Renderer::uploaded_attributes(uint64_t cloud_id) const {
  return gl::Device::instance().run([this, cloud_id]() -> uint32_t {
    auto it = impl_->clouds.find(cloud_id);
    return it == impl_->clouds.end() ? 0u : it->second.uploaded;
  });
}

uint64_t Renderer::upload_count() const {
  return gl::Device::instance().run([this] { return impl_->uploads; });
}

}  // namespace pointnpr
