// The mesh_surface mark: a segment's triangle meshes drawn as surfaces into
// the segment's own colour and linear depth, after its point mark and
// depth-tested against what that drew, so points and faces of one segment
// occlude each other per pixel and every filter, the depth inpainting and
// the compositing treat the result like points. Flat or smooth Lambert
// shading from the same light parameters as the shading marks.
#include "marks/mesh_surface.h"

#include <glm/gtc/type_ptr.hpp>

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

class MeshSurface final : public Mark {
 public:
  AttributeSet attributes(const ParamValues&) const override { return {}; }  // reads no point attributes
  MarkExtent extent(const ParamValues&) const override { return {0.0, 1.0f}; }

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
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.fbo);
    const MarkRasterState state(ctx.targets, clip);
    const float zero = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &zero);  // reversed Z, as the GL_POINTS path
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE);  // open meshes show their insides
    glDisable(GL_BLEND);      // opaque faces (the ink layer may have left blending on)
    prog.use();
    glUniformMatrix4fv(prog.location("u_projection"), 1, GL_FALSE, glm::value_ptr(glm::mat4(cam.projection)));
    glUniform1f(prog.location("u_near"), float(cam.clip_start));
    glUniform1f(prog.location("u_far"), float(cam.clip_end));
    glUniform1i(prog.location("u_ortho"), cam.orthographic ? 1 : 0);
    const int shading = p.get_enum("shading");
    glUniform1i(prog.location("u_shading"), shading);
    glUniform1f(prog.location("u_shading_strength"), float(p.get_float("shading_strength")));
    glUniform3fv(prog.location("u_light_dir"), 1, glm::value_ptr(view_light_direction(p, cam)));
    glUniform4fv(prog.location("u_constant_color"), 1, glm::value_ptr(p.get_color("color")));
    glBindTextureUnit(1, points_depth.id());
    glUniform1i(prog.location("u_points_depth"), 1);
    glUniform1i(prog.location("u_texture"), 0);
    const SurfaceColor wanted = SurfaceColor(p.get_enum("color_source"));
    for (const VisibleMesh& v : ctx.meshes) {
      const GpuMesh& g = *v.gpu;
      const SurfaceColor source = resolve(wanted, g, *v.mesh);
      const gl::Buffer* normals = shading == 2 ? g.find(MeshAttribute::Normal) : nullptr;
      const gl::Buffer* colors = source == SurfaceColor::Colors ? g.find(MeshAttribute::Color) : nullptr;
      const gl::Buffer* uvs = source == SurfaceColor::Texture ? g.find(MeshAttribute::Uv) : nullptr;
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.positions.id());
      // Unused bindings get the positions: a valid buffer the shader never reads.
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, (normals ? *normals : g.positions).id());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, (colors ? *colors : g.positions).id());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, (uvs ? *uvs : g.positions).id());
      if (uvs) glBindTextureUnit(0, g.texture.id());
      glUniform1i(prog.location("u_smooth"), normals ? 1 : 0);
      glUniform1i(prog.location("u_color_source"), int(source));
      const glm::vec4 base = v.mesh->base_color();
      glUniform4fv(prog.location("u_base_color"), 1, glm::value_ptr(base));
      glUniformMatrix4fv(prog.location("u_view_from_mesh"), 1, GL_FALSE, glm::value_ptr(v.view_from_mesh));
      const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(v.view_from_mesh)));
      glUniformMatrix3fv(prog.location("u_normal_matrix"), 1, GL_FALSE, glm::value_ptr(normal_matrix));
      glBindVertexArray(g.vao.id());
      glDrawArrays(GL_TRIANGLES, 0, GLsizei(v.mesh->indices().size()));
    }
    glBindVertexArray(0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }
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
