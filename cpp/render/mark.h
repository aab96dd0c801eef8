#pragma once
// Marks: how a segment's points become marks on the picture (round splats,
// hatching strokes, ...). A mark is one .cpp in marks/ that declares its
// Schema and registers itself, plus its GLSL in shaders/.
//
// A mark writes the segment's raster images: colour (RGBA32F, straight
// alpha, display sRGB, alpha = coverage) and linear view depth (R32F, +inf
// where empty; finite exactly where coverage > 0), within `ctx.clip`. Every
// filter, the depth inpainting and the compositing read those, whichever
// mark made them.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/params.h"
#include "gl/objects.h"
#include "gl/shaders.h"
#include "render/attributes.h"
#include "render/filter.h"  // Rect
#include "render/gpu_cloud.h"
#include "render/gpu_mesh.h"
#include "render/host_scratch.h"
#include "render/native_limits.h"
#include "render/registry.h"

namespace pointnpr {

struct Camera;
class ImageTextures;

// A chunk that survived culling, with its float view transform (composed in
// double on the CPU, so float holds at any georeferenced offset).
struct VisibleChunk {
  const GpuCloud* gpu = nullptr;
  const PointChunk* chunk = nullptr;
  glm::mat4 view_from_chunk{1.0f};
  uint32_t key_base = 0;  // segment-wide index of the chunk's first point
  // Projected screen area M of the chunk (pixels, not clipped to the
  // image): the convex hull of its box's 8 projected corners, or, for a mark
  // drawing by the queue, the area its points sample seen at the chunk's
  // depth where that is less (a box mostly empty; renderer.cpp);
  // negative where the box crosses the camera plane (every point drawn).
  double screen_area = -1.0;
  // At most this many of the chunk's queue order, set by the frame's point
  // budget (render/point_budget.h); the mark's own count where that is less.
  uint32_t budget_count = UINT32_MAX;
};

// The cloud a visible chunk's points come from, held while a native pass
// reads it; GLError naming `what` where it is gone.
std::shared_ptr<const PointCloud> chunk_cloud(const VisibleChunk& v, const char* what);
// The median spacing of a visible chunk's cloud (the mean distance to its
// k nearest neighbours, LocalResolution::median_r; computed once per cloud
// by its analysis), or `otherwise` where the cloud has none.
float median_spacing(const VisibleChunk& v, int k, float otherwise);
// The sparse spacing of a visible chunk's cloud (LocalResolution::sparse_r:
// nine in ten of its points lie at most this far from their k nearest
// neighbours) in the cloud's units, or `otherwise` where it has none.
float sparse_spacing(const VisibleChunk& v, int k, float otherwise);
// The sparse spacing of a visible chunk's cloud (LocalResolution::sparse_r
// of its k nearest neighbours, computed once per cloud) in view units (its
// instance's scale applied); 0 where the cloud has none.
float view_spacing(const VisibleChunk& v, int k);
// How the chunk's view scales its cloud's lengths (its instance's scale).
float view_scale(const VisibleChunk& v);

// A mesh that survived culling (the mesh_surface mark's input), with its
// view transform composed in double (its offsets from the mesh origin
// are float; the setup applies it in double).
struct VisibleMesh {
  const GpuMesh* gpu = nullptr;
  const TriangleMesh* mesh = nullptr;
  glm::dmat4 view_from_mesh{1.0};
};

// The frame's images a mark draws with. `color` and `depth` are the outputs
// (cleared to transparent and +inf over the segment's work area); the rest
// is scratch shared by the marks.
struct MarkTargets {
  glm::ivec2 size{0, 0};          // the images' size (a tile's region, or the frame)
  // Frame drawn in tiles (render/tiling.h): the images hold the frame's
  // pixels [origin, origin + size); frame_size is the whole frame's, which
  // the projection maps to. `ctx.clip` and every image access are local.
  glm::ivec2 origin{0, 0};
  glm::ivec2 frame_size{0, 0};
  bool int64_atomics = false;
  const gl::Texture* color = nullptr;
  const gl::Texture* depth = nullptr;
  const gl::Texture* gl_depth = nullptr;  // DEPTH_COMPONENT32F for GL draws
  GLuint fbo = 0;                         // color0 = color, color1 = depth, depth = gl_depth
  // Where the filter chain fills gaps (Style::fills_gaps): the points mark
  // writes each pixel's point's spacing (SplatRadius, view units) here, and
  // spacing_fbo is fbo with it as color2. Null otherwise.
  const gl::Texture* spacing = nullptr;
  GLuint spacing_fbo = 0;
  const gl::Buffer* depth_keys = nullptr; // per pixel uint (uint64 with int64 atomics), cleared to ~0
  const gl::Buffer* keys = nullptr;       // per pixel uint (32-bit path), cleared to ~0
  // Frame-sized scratch textures of a format, by index; contents undefined.
  std::function<const gl::Texture&(GLenum format, int index)> scratch;
  // Scratch buffers (dynamic storage) of at least `bytes`, by index, kept
  // between frames and segments so marks do not allocate per frame;
  // contents undefined.
  std::function<const gl::Buffer&(size_t bytes, int index)> scratch_buffer;
};

// The frame's size the projection maps to (the images' when not tiled).
inline glm::ivec2 frame_size(const MarkTargets& t) { return t.frame_size.x > 0 ? t.frame_size : t.size; }
// GL draws into the images: the viewport is the frame's, moved by the tile's origin.
inline void set_frame_viewport(const MarkTargets& t) {
  const glm::ivec2 frame = frame_size(t);
  glViewport(-t.origin.x, -t.origin.y, frame.x, frame.y);
}

// The raster state of a mark's GL passes, for one scope: the frame's
// viewport (moved by a tile's origin), the scissor on the clip rect and
// reversed Z's [0, 1] clip depth; restored to the GL defaults the other
// passes expect (no blending, depth writes on, no depth test or scissor,
// the default framebuffer) when it ends. The framebuffer is the pass's to bind.
// The scissor on a mark's clip rect and reversed Z's [0, 1] clip depth.
void set_mark_clip(const Rect& clip);
// The GL defaults the other passes expect: no blending, depth writes on,
// no depth test or scissor, GL's clip depth, the default framebuffer.
void restore_raster_defaults();

// A mark drawn on the CPU (the native paths): its RGBA float colour and
// depth over `clip` (rows of clip's width) uploaded into the targets' images,
// and the covered bounds, from each row's covered span [x, y] (y < 0: none),
// given to `coverage` when the renderer asks for them. `what` names the
// mark in a GL error.
void upload_cpu_mark(const MarkTargets& targets, const Rect& clip, const float* rgba, const float* depth,
                     const std::vector<glm::ivec2>& row_span, std::optional<Rect>* coverage, const char* what);

class MarkRasterState {
 public:
  MarkRasterState(const MarkTargets& targets, const Rect& clip);
  ~MarkRasterState();
  MarkRasterState(const MarkRasterState&) = delete;
  MarkRasterState& operator=(const MarkRasterState&) = delete;
};

// One stroke / splat a mark placed, when the caller asked to see them
// (tests of coherence and direction, debugging).
struct CapturedMark {
  uint32_t point_id = 0;
  glm::vec3 center{0.0f};     // view space
  glm::vec3 direction{0.0f};  // view space, unit (first line)
  glm::vec3 normal{0.0f};     // view space, unit (the surface it lies on)
  bool crossed = false;       // a second, crossing line
  float length = 0.0f;        // scene units
  glm::vec4 color{0.0f};      // display sRGB, alpha = stroke opacity
  uint32_t kind = 0;          // the mark's class of point (feature_strokes: 0 directional, 1 non-directional, 2 dithering)
};

// What a mark computes once per frame for all its tiles (stipples: the
// light-view quadtree, counts over every visible point). CPU memory only:
// it is freed off the GL thread.
struct MarkFrameCache {
  virtual ~MarkFrameCache() = default;
};

struct MarkContext {
  gl::ShaderLibrary* shaders = nullptr;
  ImageTextures* images = nullptr;
  const Camera* camera = nullptr;
  MarkTargets targets;
  std::span<const VisibleChunk> chunks;
  std::span<const VisibleMesh> meshes;  // for mesh_surface; empty for the point marks
  Rect clip;                    // screen bounds of the chunks (+ the mark's extent)
  // The segment in the whole frame (a tile's `chunks` and `clip` are what
  // reaches it): every visible chunk, their rectangle in frame pixels, and
  // a cache that lives for the frame (empty at its first tile).
  std::span<const VisibleChunk> frame_chunks;
  Rect frame_clip;
  std::unique_ptr<MarkFrameCache>* frame_cache = nullptr;
  double depth_min = 0.0;       // view depth range of the visible chunks' bounds
  double depth_max = 1.0;
  double time = 0.0;
  uint32_t segment_seed = 0;
  NativeLimits native;  // RenderSettings::native: the native backends' limits for this call
  HostScratch* host = nullptr;  // the renderer's: what native backends keep between frames
  // The frame's memory budget (RenderSettings::memory_budget or the
  // default): what a native backend's host records may take, at most.
  size_t memory_budget = 0;
  std::map<std::string, double>* stats = nullptr;
  std::vector<std::string>* warnings = nullptr;
  std::vector<CapturedMark>* capture = nullptr;  // null unless asked
  // A mark that knows the bounds of the pixels it covered (local, empty if
  // none) may set them here, sparing the renderer a pass over the depth.
  std::optional<Rect>* coverage = nullptr;
};

// How far beyond its points a mark may draw: added to the chunks' bounds
// before culling and to their screen rectangle.
struct MarkExtent {
  double world = 0.0;   // scene units around every point
  float pixels = 0.0f;  // pixels around every projected point
};

class Mark {
 public:
  virtual ~Mark() = default;
  // The per-point attributes the mark reads with these parameters.
  virtual AttributeSet attributes(const ParamValues& params) const = 0;
  virtual MarkExtent extent(const ParamValues& params) const = 0;
  virtual void draw(const MarkContext& ctx, const ParamValues& params) const = 0;
  // Whether draw() honours MarkTargets::origin and frame_size, drawing a
  // tile the same bytes as that part of the whole frame; frames of marks
  // that do not are drawn whole (over the memory budget, with a warning).
  virtual bool draws_tiles(const ParamValues& /*params*/) const { return false; }
  // Pixels beyond a tile that the mark's screen-space passes read (blurs,
  // neighbourhoods), beyond its extent: part of the tiles' halo.
  virtual int screen_reach(const ParamValues& /*params*/) const { return 0; }
};

struct MarkInfo {
  static constexpr const char* kKind = "mark";
  Schema schema;
  std::function<std::unique_ptr<Mark>()> create;
};

const std::vector<const MarkInfo*>& registered_marks();
const MarkInfo& find_mark(const std::string& id);  // throws ParameterError
using MarkRegistration = Registration<MarkInfo>;

// Colour sources shared by the marks (the `color_source` parameter).
enum class ColorSource { Rgb = 0, Intensity = 1, Classification = 2, Constant = 3, Auto = 4 };
ParamSpec color_source_param();
// The colour a mark lays under its `marks` ("strokes", "dots") where the
// surface is: the ink resolve's paper (alpha: its opacity).
ParamSpec paper_color_param(glm::dvec4 def, const std::string& marks);
// The attributes a colour source reads (auto: any of the three).
AttributeSet color_attributes(ColorSource source);
// The source a cloud can serve: auto picks RGB, else intensity, else the
// classification palette; a source the cloud lacks becomes constant.
ColorSource resolve_color_source(ColorSource source, const GpuCloud& cloud);

// The continuous resolution queue (seed 001 sections 6.3, 7.2), for every
// mark: each chunk's points in a stable seeded order (AttributeKind::
// QueueOrder, cached per cloud); a mark drawing "constant on screen" draws
// only the first queue_count() of them, level x M points for a projected
// area of M pixels, so the density of marks on screen stays constant as the
// camera moves and one more pixel of area adds at most one point at the
// queue's end. The shared parameters: `density_mode` (all_points,
// constant_on_screen) and `queue_level` (points per pixel of area).
ParamSpec density_mode_param();
ParamSpec queue_level_param(double default_level);
bool queue_enabled(const ParamValues& params);  // density_mode == constant_on_screen
// Whether the mark draws by the queue order this frame: its own density
// mode, or the frame's point budget cutting some chunk short.
bool draws_queue(const MarkContext& ctx, const ParamValues& params);
bool draws_queue(const VisibleChunk& chunk, const ParamValues& params);  // for this chunk
// How many of the chunk's points to draw: all of them when the queue is off
// and no budget applies; the lesser of the two otherwise.
uint32_t queue_count(const VisibleChunk& chunk, const ParamValues& params);

// The light of marks that shade (hatching, stipples): `light_space`
// (world, camera, scene_sun: as world, the host putting its sun lamp's
// direction into azimuth and elevation), `light_azimuth`, `light_elevation`.
ParamSpec light_space_param(int default_space = 0);  // 0 world, 1 camera, 2 scene_sun
// A mark's light, so that points without colours of their own read as a
// shape: `schema` with `shading` none / diffuse / auto (auto: lit where the
// points' colour resolves to the constant one; files saved before it:
// none), `shading_strength` (default `strength`) and the light's space
// (camera by default) and direction. `what` says what is lit, for the docs.
Schema with_surface_light(Schema schema, const std::string& what, double strength);
// Whether a chunk whose colour resolves to `resolved` is lit (shading).
bool lit_by_shading(const ParamValues& p, ColorSource resolved);
ParamSpec light_azimuth_param(double default_deg);
ParamSpec light_elevation_param(double default_deg);
// A world direction from azimuth (around Z) and elevation (above XY), degrees.
glm::dvec3 world_direction(double azimuth_deg, double elevation_deg);
// Toward the light, in view space: world (and scene_sun) directions turned
// by the camera (composed in double); camera lights as the points mark's
// (elevation away from the view axis, azimuth around it).
glm::vec3 view_light_direction(const ParamValues& params, const Camera& camera);

// Binds a chunk's positions (binding 0), colour attribute (1) and, when
// given, a further attribute buffer per binding, and sets the uniforms of
// shaders/point_attributes.glsl (u_color_source, u_intensity_scale,
// u_view_from_chunk, u_normal_matrix, u_first, u_count, u_key_base).
void bind_chunk(const gl::Program& program, const VisibleChunk& chunk, ColorSource source,
                const std::vector<std::pair<int, const gl::Buffer*>>& extra = {});

}  // namespace pointnpr
