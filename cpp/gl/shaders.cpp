#include "gl/shaders.h"

#include <cstdlib>
#include <fstream>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "gl/device.h"

namespace pointnpr::gl {

namespace {
std::mutex g_dir_mutex;
std::string g_dir;

std::string read_file(const std::string& name) {
  const std::string path = shader_dir() + "/" + name;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw GLError("shader file not found: " + path + " (is the shaders/ folder installed next to _pointnpr?)");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Resolves `#include "file"` once per file (shared GLSL helpers).
std::string expand_includes(const std::string& name, std::set<std::string>& seen) {
  if (!seen.insert(name).second) return "";
  static const std::regex include_re(R"(^\s*#include\s+"([^"]+)\"\s*$)");
  std::istringstream in(read_file(name));
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_match(line, m, include_re)) {
      out << expand_includes(m[1].str(), seen) << "\n";
    } else {
      out << line << "\n";
    }
  }
  return out.str();
}

std::string build_source(const std::string& file, const std::vector<std::string>& defines) {
  std::string src = "#version 450 core\n";
  for (const auto& d : defines) src += "#define " + d + "\n";
  std::set<std::string> seen;
  src += "#line 1\n" + expand_includes(file, seen);
  return src;
}

// The info log of a shader or program (same calls, different entry points).
template <void (*GetIv)(GLuint, GLenum, GLint*), void (*GetLog)(GLuint, GLsizei, GLsizei*, GLchar*)>
std::string info_log(GLuint object) {
  GLint len = 0;
  GetIv(object, GL_INFO_LOG_LENGTH, &len);
  std::string log(size_t(len > 0 ? len : 1), '\0');
  GetLog(object, len, nullptr, log.data());
  return log;
}

GLuint compile(GLenum stage, const std::string& file, const std::vector<std::string>& defines) {
  const std::string src = build_source(file, defines);
  GLuint shader = glCreateShader(stage);
  const char* text = src.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log<glGetShaderiv, glGetShaderInfoLog>(shader);
    glDeleteShader(shader);
    throw GLError("shader " + file + " failed to compile:\n" + log);
  }
  return shader;
}

GLuint link(const std::vector<GLuint>& shaders, const std::string& what) {
  GLuint program = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(program, s);
  glLinkProgram(program);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log<glGetProgramiv, glGetProgramInfoLog>(program);
    glDeleteProgram(program);
    throw GLError("program " + what + " failed to link:\n" + log);
  }
  return program;
}

std::string cache_key(const std::string& files, const std::vector<std::string>& defines) {
  std::string key = files;
  for (const auto& d : defines) key += "|" + d;
  return key;
}
}  // namespace

void set_shader_dir(const std::string& dir) {
  std::lock_guard lock(g_dir_mutex);
  g_dir = dir;
}

std::string shader_dir() {
  std::lock_guard lock(g_dir_mutex);
  if (!g_dir.empty()) return g_dir;
  if (const char* env = std::getenv("POINTNPR_SHADER_DIR"); env && *env) return env;
  return POINTNPR_SHADER_SOURCE_DIR;
}

const Program& ShaderLibrary::compute(const std::string& file, const std::vector<std::string>& defines) {
  const std::string key = cache_key(file, defines);
  auto it = cache_.find(key);
  if (it != cache_.end()) return it->second;
  GLuint cs = compile(GL_COMPUTE_SHADER, file, defines);
  return cache_.emplace(key, Program(link({cs}, file))).first->second;
}

const Program& ShaderLibrary::graphics(const std::string& vert, const std::string& frag,
                                       const std::vector<std::string>& defines) {
  const std::string key = cache_key(vert + "+" + frag, defines);
  auto it = cache_.find(key);
  if (it != cache_.end()) return it->second;
  GLuint vs = compile(GL_VERTEX_SHADER, vert, defines);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, frag, defines);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  return cache_.emplace(key, Program(link({vs, fs}, vert + "+" + frag))).first->second;
}

void check_uniform_block(const Program& program, const char* block, size_t bytes, GLuint binding) {
  const GLuint index = glGetUniformBlockIndex(program.id(), block);
  if (index == GL_INVALID_INDEX) throw GLError(std::string("uniform block ") + block + " not found in its program");
  GLint size = 0;
  glGetActiveUniformBlockiv(program.id(), index, GL_UNIFORM_BLOCK_DATA_SIZE, &size);
  if (size_t(size) != (bytes + 15) / 16 * 16)
    throw GLError(std::string("uniform block ") + block + ": " + std::to_string(size) + " bytes in GLSL, " +
                  std::to_string(bytes) + " in C++ (their layouts differ)");
  glUniformBlockBinding(program.id(), index, binding);
}

}  // namespace pointnpr::gl
