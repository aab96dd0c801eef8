#include "gl/objects.h"

#include "core/error.h"
#include "gl/device.h"

namespace pointnpr::gl {

void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void delete_texture(GLuint id) { glDeleteTextures(1, &id); }
void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void delete_program(GLuint id) { glDeleteProgram(id); }

Texture::Texture(GLenum internal_format, glm::ivec2 size, int levels) : size_(size), format_(internal_format) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  handle_ = Handle<delete_texture>(id);
  glTextureStorage2D(id, levels, internal_format, size.x, size.y);
  glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  check_gl("texture allocation");
}

Buffer make_buffer(size_t bytes, const void* data, GLbitfield flags) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  Buffer buffer(id);
  glNamedBufferStorage(id, GLsizeiptr(bytes ? bytes : 4), data, flags);
  check_gl("buffer allocation");
  return buffer;
}

}  // namespace pointnpr::gl
