// The mesh_surface mark: a segment's triangle meshes drawn as surfaces into
// the segment's own colour and linear depth, after its point mark and
// depth-tested against what that drew, so points and faces of one segment
// occlude each other per pixel and every filter, the depth inpainting and
// the compositing treat the result like points. Flat or smooth Lambert
// shading from the same light parameters as the shading marks. Pixels are
// decided per frame pixel (shaders/mesh_surface_common.glsl), so frames
// draw in tiles with the bytes of the whole frame.
#include "marks/mesh_surface/mesh_surface.h"

#include <algorithm>
#include <limits>
#include <span>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "render/mark.h"
#include "scene/camera.h"

namespace pointnpr {
namespace {

// Where surface colours come from; auto: the texture where the mesh has one
// (and UVs), else its colour attribute, else its base colour, else constant.
enum class SurfaceColor { Auto = 0, BaseColor = 1, Colors = 2, Texture = 3, Constant = 4 };

SurfaceColor resolve(SurfaceColor c, const GpuMesh& g, const TriangleMesh& m) {
  const bool texture = g.texture.id() != 0 && g.find(MeshAttribute::Uv);
  const bool colors = g.find(MeshAttribute::Color) != nullptr;
  switch (c) {
    case SurfaceColor::Auto:
      if (texture) return SurfaceColor::Texture;
      if (colors) return SurfaceColor::Colors;
      return m.has_base_color() ? SurfaceColor::BaseColor : SurfaceColor::Constant;
    case SurfaceColor::BaseColor: return m.has_base_color() ? c : SurfaceColor::Constant;
    case SurfaceColor::Colors: return colors ? c : SurfaceColor::Constant;
    case SurfaceColor::Texture: return texture ? c : SurfaceColor::Constant;
    case SurfaceColor::Constant: return c;
  }
  return SurfaceColor::Constant;
}

// shaders/mesh_surface_common.glsl's TriangleRaster (std430: eight vec4).
struct TriangleRaster {
  glm::vec4 corners[2];  // the triangle GL draws, frame pixels: xy, zw of [0]; xy of [1]
  glm::vec4 edge[3];     // xyz: the homogeneous edge functions (b x c, c x a, a x b); edge[0].w: their determinant
  glm::vec4 view[3];     // xyz: the corners in view space
};
static_assert(sizeof(TriangleRaster) == 8 * 16);

// How far the drawn triangle's edges lie outside the mesh's triangle, in
// pixels: more than GL's window coordinates can round differently with a
// tile's viewport (a few thousandths of a pixel at 16k), so every pixel
// whose centre the triangle covers is drawn in any tile.
constexpr double kGrow = 1.0 / 32.0;
// Corners moving farther than this (very thin triangles) draw the
// rectangle instead.
constexpr double kMaxCornerShift = 8.0;
// Margin of the rectangle around the projected corners, in pixels.
constexpr double kRectMargin = 0.125;

// The drawn triangle of a triangle wholly in front of the camera with
// screen corners s: its edges moved out by kGrow. False when too thin.
bool grown_triangle(const glm::dvec2 (&s)[3], glm::dvec2 (&out)[3]) {
  const glm::dvec2 a = s[1] - s[0], b = s[2] - s[0];
  const double area2 = a.x * b.y - a.y * b.x;
  if (!(std::abs(area2) > 1e-9)) return false;
  const double turn = area2 > 0.0 ? 1.0 : -1.0;
  glm::dvec2 normal[3];
  double offset[3];
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 d = s[(k + 1) % 3] - s[k];
    normal[k] = glm::normalize(glm::dvec2(d.y, -d.x) * turn);  // outward
    offset[k] = glm::dot(normal[k], s[k]) + kGrow;
  }
  for (int k = 0; k < 3; ++k) {  // corner k: where the moved edges k - 1 and k meet
    const glm::dvec2 n0 = normal[(k + 2) % 3], n1 = normal[k];
    const double o0 = offset[(k + 2) % 3], o1 = offset[k];
    const double det = n0.x * n1.y - n0.y * n1.x;
    if (std::abs(det) < 1e-12) return false;
    out[k] = glm::dvec2((o0 * n1.y - o1 * n0.y) / det, (n0.x * o1 - n1.x * o0) / det);
    if (!(glm::length(out[k] - s[k]) <= kMaxCornerShift)) return false;
  }
  return true;
}

// What the fragments of triangles [first, first + out.size()) need, in
// double and per triangle (so any thread count gives the same bytes). A
// compute pass doing the same measured no faster on llvmpipe; here the
// mesh's double-precision placement is kept to the end.
void set_up_triangles(const TriangleMesh& mesh, const glm::dmat4& view_from_mesh, const Camera& cam,
                      glm::dvec2 frame, const Rect& frame_clip, size_t first, std::span<TriangleRaster> out) {
  const std::vector<glm::vec3>& positions = mesh.local_positions();
  const std::vector<uint32_t>& indices = mesh.indices();
  // Perspective: the part at or beyond the near plane (the fragments
  // discard the rest), so a triangle reaching behind the camera gets the
  // rectangle of its visible part; orthographic w is 1 everywhere.
  const double near_w = cam.orthographic ? -1.0 : cam.clip_start;
  const glm::dvec2 clip_lo(frame_clip.min), clip_hi(frame_clip.max);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const size_t t = first + i;
      glm::dvec3 view[3], v[3];
      for (int k = 0; k < 3; ++k) {
        view[k] = glm::dvec3(view_from_mesh * glm::dvec4(glm::dvec3(positions[indices[3 * t + k]]), 1.0));
        const glm::dvec4 c = cam.projection * glm::dvec4(view[k], 1.0);
        v[k] = glm::dvec3(c.x, c.y, c.w);  // clip x, y, w: depth is the interpolated view depth
      }
      TriangleRaster& o = out[i];
      glm::dvec2 drawn[3];
      bool in_front = true;
      glm::dvec2 screen[3];
      for (int k = 0; k < 3; ++k) {
        in_front = in_front && v[k].z >= near_w;
        screen[k] = (glm::dvec2(v[k]) / v[k].z + 1.0) * 0.5 * frame;
      }
      if (!in_front || !grown_triangle(screen, drawn)) {
        // The rectangle of the pixels whose centres it may cover (of its
        // visible part, for one reaching behind the camera), drawn as one
        // right triangle with legs twice its sides at integer pixels, whose
        // coverage of the rectangle no viewport origin changes.
        glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
        const auto extend = [&](glm::dvec3 p) {
          const glm::dvec2 q = (glm::dvec2(p) / p.z + 1.0) * 0.5 * frame;
          lo = glm::min(lo, q);
          hi = glm::max(hi, q);
        };
        for (int k = 0; k < 3; ++k) {
          const glm::dvec3 p = v[k], q = v[(k + 1) % 3];
          if (p.z >= near_w) extend(p);
          if ((p.z - near_w) * (q.z - near_w) < 0.0) extend(glm::mix(p, q, (near_w - p.z) / (q.z - p.z)));
        }
        glm::dvec2 rect_lo = glm::clamp(glm::ceil(lo - 0.5 - kRectMargin), clip_lo, clip_hi);
        glm::dvec2 rect_hi = glm::clamp(glm::floor(hi - 0.5 + kRectMargin) + 1.0, clip_lo, clip_hi);
        if (!(lo.x <= hi.x && lo.y <= hi.y)) rect_hi = rect_lo;  // nothing in front, or not finite
        const glm::dvec2 size = glm::max(rect_hi - rect_lo, glm::dvec2(0.0));
        drawn[0] = rect_lo;
        drawn[1] = rect_lo + glm::dvec2(2.0 * size.x, 0.0);
        drawn[2] = rect_lo + glm::dvec2(0.0, 2.0 * size.y);
      }
      o.corners[0] = glm::vec4(drawn[0].x, drawn[0].y, drawn[1].x, drawn[1].y);
      o.corners[1] = glm::vec4(drawn[2].x, drawn[2].y, 0.0f, 0.0f);
      const glm::dvec3 e0 = glm::cross(v[1], v[2]), e1 = glm::cross(v[2], v[0]), e2 = glm::cross(v[0], v[1]);
      o.edge[0] = glm::vec4(glm::vec3(e0), float(glm::dot(v[0], e0)));
      o.edge[1] = glm::vec4(glm::vec3(e1), 0.0f);
      o.edge[2] = glm::vec4(glm::vec3(e2), 0.0f);
      for (int k = 0; k < 3; ++k) o.view[k] = glm::vec4(glm::vec3(view[k]), 0.0f);
    }
  });
}

class MeshSurface final : public Mark {
 public:
  AttributeSet attributes(const ParamValues&) const override { return {}; }  // reads no point attributes
  MarkExtent extent(const ParamValues&) const override { return {0.0, 1.0f}; }
  bool draws_tiles(const ParamValues&) const override { return true; }

  void draw(const MarkContext& ctx, const ParamValues& p) const override {
    if (ctx.meshes.empty() || ctx.clip.empty()) return;
    const Camera& cam = *ctx.camera;
    const Rect& clip = ctx.clip;
    // The point mark's depth, read by the fragments (a copy: the depth
    // image is also written by this draw).
    const gl::Texture& points_depth = ctx.targets.scratch(GL_R32F, 0);
    glCopyImageSubData(ctx.targets.depth->id(), GL_TEXTURE_2D, 0, clip.min.x, clip.min.y, 0, points_depth.id(),
                       GL_TEXTURE_2D, 0, clip.min.x, clip.min.y, 0, clip.size().x, clip.size().y, 1);
    const gl::Program& prog = ctx.shaders->graphics("mesh_surface.vert", "mesh_surface.frag");
    const glm::ivec2 origin = ctx.targets.origin;
    const glm::ivec2 frame = frame_size(ctx.targets);
    const Rect frame_clip{clip.min + origin, clip.max + origin};
    prog.use();
    glUniform2f(prog.location("u_frame"), float(frame.x), float(frame.y));
    glUniform2i(prog.location("u_origin"), origin.x, origin.y);
    glUniform1f(prog.location("u_near"), float(cam.clip_start));
    glUniform1i(prog.location("u_ortho"), cam.orthographic ? 1 : 0);
    glUniform1f(prog.location("u_far"), float(cam.clip_end));
    const int shading = p.get_enum("shading");
    glUniform1i(prog.location("u_shading"), shading);
    glUniform1f(prog.location("u_shading_strength"), float(p.get_float("shading_strength")));
    glUniform3fv(prog.location("u_light_dir"), 1, glm::value_ptr(view_light_direction(p, cam)));
    glUniform4fv(prog.location("u_constant_color"), 1, glm::value_ptr(p.get_color("color")));
    glUniform1i(prog.location("u_points_depth"), 1);
    glUniform1i(prog.location("u_texture"), 0);

    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.fbo);
    const MarkRasterState state(ctx.targets, clip);
    const float zero = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &zero);  // reversed Z, as the GL_POINTS path
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);  // open meshes show their insides
    glDisable(GL_BLEND);      // opaque faces (the ink layer may have left blending on)
    glBindTextureUnit(1, points_depth.id());
    const SurfaceColor wanted = SurfaceColor(p.get_enum("color_source"));
    for (const VisibleMesh& v : ctx.meshes) {
      const GpuMesh& g = *v.gpu;
      const SurfaceColor source = resolve(wanted, g, *v.mesh);
      const gl::Buffer* normals = shading == 2 ? g.find(MeshAttribute::Normal) : nullptr;
      const gl::Buffer* colors = source == SurfaceColor::Colors ? g.find(MeshAttribute::Color) : nullptr;
      const gl::Buffer* uvs = source == SurfaceColor::Texture ? g.find(MeshAttribute::Uv) : nullptr;
      // Unused bindings get the positions: a valid buffer the shader never
      // reads (the corners' positions come with the setup).
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, (normals ? *normals : g.positions).id());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, (colors ? *colors : g.positions).id());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, (uvs ? *uvs : g.positions).id());
      if (uvs) glBindTextureUnit(0, g.texture.id());
      glUniform1i(prog.location("u_smooth"), normals ? 1 : 0);
      glUniform1i(prog.location("u_color_source"), int(source));
      glUniform4fv(prog.location("u_base_color"), 1, glm::value_ptr(v.mesh->base_color()));
      const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_mesh)));
      glUniformMatrix3fv(prog.location("u_normal_matrix"), 1, GL_FALSE, glm::value_ptr(normal_matrix));
      glBindVertexArray(g.vao.id());
      // In batches, in the mesh's order (ties in depth go to the first
      // drawn), with a bounded scratch of per-triangle setup.
      const size_t triangles = v.mesh->num_triangles();
      const size_t batch_size = std::min(triangles, kSetupBatch);
      const gl::Buffer& rasters = ctx.targets.scratch_buffer(batch_size * sizeof(TriangleRaster), 0);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, rasters.id());
      std::vector<TriangleRaster> setup(batch_size);
      for (size_t first = 0; first < triangles; first += kSetupBatch) {
        const size_t count = std::min(kSetupBatch, triangles - first);
        set_up_triangles(*v.mesh, v.view_from_mesh, cam, glm::dvec2(frame), frame_clip, first,
                         std::span(setup).first(count));
        glNamedBufferSubData(rasters.id(), 0, GLsizeiptr(count * sizeof(TriangleRaster)), setup.data());
        glUniform1ui(prog.location("u_first"), GLuint(first));
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(count * 3));
      }
    }
    glBindVertexArray(0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }

 private:
  static constexpr size_t kSetupBatch = size_t(1) << 18;  // 28 MiB of setup at most
};

const MarkRegistration registration{{
    Schema{"mesh_surface",
           "Mesh Surface",
           "Draws the segment's objects with faces as shaded triangles into its colour and depth, occluding its "
           "points per pixel (every style has one, beside its point mark); or hands them to the point mark as "
           "their vertices or as points sampled on their surface.",
           {
               enum_param("meshes", {"surface", "points", "sampled"}, 0,
                          "surface: triangles; points: the vertices, drawn by the style's point mark; sampled: "
                          "points sampled on the surface (stable, seeded by triangle), drawn by the point mark"),
               only_when(float_param("sample_density", 400.0, 0.01, 1.0e6, "1/m^2",
                                     "Points sampled per square scene unit of surface (meshes = sampled)"),
                         "meshes", {"sampled"}),
               only_when(enum_param("color_source", {"auto", "base_color", "colors", "texture", "constant"}, 0,
                                    "auto: the base-colour texture where there is one, else the colour attribute, "
                                    "else the material's base colour, else the constant colour"),
                         "meshes", {"surface"}),
               only_when(color_param("color", {0.8, 0.8, 0.8, 1.0}, "Constant color (display sRGB)"), "meshes",
                         {"surface"}),
               only_when(enum_param("shading", {"none", "flat", "smooth"}, 2,
                                    "Lambert shading by the face normals (flat) or the area-weighted vertex normals "
                                    "(smooth)"),
                         "meshes", {"surface"}),
               only_when(float_param("shading_strength", 0.7, 0.0, 1.0, "",
                                     "How dark surfaces turned away from the light get"),
                         "shading", {"flat", "smooth"}),
               only_when(light_space_param(), "shading", {"flat", "smooth"}),
               only_when(light_azimuth_param(135.0), "shading", {"flat", "smooth"}),
               only_when(light_elevation_param(45.0), "shading", {"flat", "smooth"}),
           }},
    [] { return std::make_unique<MeshSurface>(); }}};

}  // namespace

MeshMode mesh_mode(const ParamValues& p) { return MeshMode(p.get_enum("meshes")); }

double mesh_sample_density(const ParamValues& p) { return p.get_float("sample_density"); }

std::set<MeshAttribute> mesh_attributes(const ParamValues& p) {
  std::set<MeshAttribute> out;
  if (mesh_mode(p) != MeshMode::Surface) return out;
  if (p.get_enum_name("shading") == "smooth") out.insert(MeshAttribute::Normal);
  const std::string source = p.get_enum_name("color_source");
  if (source == "auto" || source == "colors") out.insert(MeshAttribute::Color);
  if (source == "auto" || source == "texture") out.insert({MeshAttribute::Uv, MeshAttribute::Texture});
  return out;
}

}  // namespace pointnpr
