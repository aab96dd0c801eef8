#pragma once
#include <initializer_list>
// Move-only owners of GL names. Created and destroyed on the GL thread.
#include <glm/vec2.hpp>
#include <utility>

#include "gl/gl.h"

namespace pointnpr::gl {

template <void (*Delete)(GLuint)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void delete_buffer(GLuint id);
void delete_texture(GLuint id);
void delete_framebuffer(GLuint id);
void delete_vertex_array(GLuint id);
void delete_program(GLuint id);

using Buffer = Handle<delete_buffer>;
using Framebuffer = Handle<delete_framebuffer>;
using VertexArray = Handle<delete_vertex_array>;
using ProgramHandle = Handle<delete_program>;

// A 2D texture with immutable storage and its size.
class Texture {
 public:
  Texture() = default;
  Texture(GLenum internal_format, glm::ivec2 size, int levels = 1);
  GLuint id() const { return handle_.id(); }
  glm::ivec2 size() const { return size_; }
  GLenum format() const { return format_; }

 private:
  Handle<delete_texture> handle_;
  glm::ivec2 size_{0, 0};
  GLenum format_ = 0;
};

// Buffer with immutable storage of `bytes`, optionally initialised.
Buffer make_buffer(size_t bytes, const void* data, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);

// A framebuffer drawing to `colors` (attachments 0, 1, ... in order) with
// `depth` as its depth attachment (or none); throws GLError naming `what`
// when it is incomplete.
Framebuffer make_framebuffer(std::initializer_list<const Texture*> colors, const Texture* depth, const char* what);

}  // namespace pointnpr::gl
