#pragma once
// GLSL lives in shaders/ beside the installed module. Programs are compiled
// on first use per (files, defines) and cached for the life of the context.
#include <map>
#include <string>
#include <vector>

#include "gl/objects.h"

namespace pointnpr::gl {

// Where shaders are read from: set by the Python package to the shaders/
// folder next to _pointnpr; else $POINTNPR_SHADER_DIR; else the source tree.
void set_shader_dir(const std::string& dir);
std::string shader_dir();

class Program {
 public:
  Program() = default;
  explicit Program(GLuint id) : handle_(id) {}
  GLuint id() const { return handle_.id(); }
  void use() const { glUseProgram(handle_.id()); }
  GLint location(const char* name) const { return glGetUniformLocation(handle_.id(), name); }

 private:
  ProgramHandle handle_;
};

// Throws unless the program's std140 uniform block `block` is as large as
// the C++ struct mirroring it (`bytes`, rounded to 16): a member the two
// lay out differently (a vec3, a scalar before a vec4) pads one of them
// (SETTINGS_BLOCK in core/glsl.h). Binds the block to `binding`.
void check_uniform_block(const Program& program, const char* block, size_t bytes, GLuint binding);

class ShaderLibrary {
 public:
  // Compute program from one file, e.g. "cartoon.comp".
  const Program& compute(const std::string& file, const std::vector<std::string>& defines = {});
  // Vertex + fragment program.
  const Program& graphics(const std::string& vert, const std::string& frag,
                          const std::vector<std::string>& defines = {});

 private:
  std::map<std::string, Program> cache_;
};

}  // namespace pointnpr::gl
