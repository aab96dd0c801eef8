#include "gl/objects.h"

#include <string>
#include <vector>

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

Framebuffer make_framebuffer(std::initializer_list<const Texture*> colors, const Texture* depth, const char* what) {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  Framebuffer fbo(id);
  std::vector<GLenum> bufs;
  for (const Texture* t : colors) {
    const GLenum attachment = GLenum(GL_COLOR_ATTACHMENT0 + bufs.size());
    glNamedFramebufferTexture(id, attachment, t->id(), 0);
    bufs.push_back(attachment);
  }
  if (depth) glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, depth->id(), 0);
  glNamedFramebufferDrawBuffers(id, GLsizei(bufs.size()), bufs.data());
  if (glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw GLError(std::string("the ") + what + " framebuffer is incomplete");
  return fbo;
}

}  // namespace pointnpr::gl
