#pragma once
/// Owning handles for the GL objects a render pass creates (buffers, vertex arrays, textures). GL
/// names are plain integers; a handle deletes its object when it goes out of scope, on every exit
/// path, exceptions included. Like every GL object they belong to the context that was current
/// when they were made: keep it alive and current until the handles are gone (gl_context.h).
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>

#include <utility>
#include <vector>

namespace sdm {

/// Owns one GL object name (0: none). Move-only; `Delete` frees one name of its kind.
template <void (*Delete)(GLuint)>
class GlObject {
 public:
  GlObject() = default;
  /// Takes ownership of `name`, e.g. the result of upload_texture().
  explicit GlObject(GLuint name) : name_(name) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  GlObject& operator=(GlObject&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = std::exchange(other.name_, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint get() const { return name_; }
  /// Deletes the object held, if any.
  void reset() {
    if (name_) Delete(name_);
    name_ = 0;
  }

 private:
  GLuint name_ = 0;
};

namespace gl_detail {
inline void delete_buffer(GLuint name) { glDeleteBuffers(1, &name); }
inline void delete_vertex_array(GLuint name) { glDeleteVertexArrays(1, &name); }
inline void delete_texture(GLuint name) { glDeleteTextures(1, &name); }
}  // namespace gl_detail

using GlBuffer = GlObject<gl_detail::delete_buffer>;
using GlVertexArray = GlObject<gl_detail::delete_vertex_array>;
using GlTexture = GlObject<gl_detail::delete_texture>;

/// A new buffer holding `data` (GL_STATIC_DRAW). An empty vector gets storage for one element,
/// left undefined, never a zero-size store (an atlas pass may have no triangle to draw). Needs a
/// current context.
template <class T>
GlBuffer make_buffer(const std::vector<T>& data) {
  GLuint name = 0;
  glCreateBuffers(1, &name);
  GlBuffer buffer(name);
  glNamedBufferData(name, GLsizeiptr((data.empty() ? 1 : data.size()) * sizeof(T)), data.empty() ? nullptr : data.data(),
                    GL_STATIC_DRAW);
  return buffer;
}

/// A new vertex array object with no attribute yet. Needs a current context.
inline GlVertexArray make_vertex_array() {
  GLuint name = 0;
  glCreateVertexArrays(1, &name);
  return GlVertexArray(name);
}

/// A new texture object of `target` (e.g. GL_TEXTURE_BUFFER) with no storage yet. Needs a current context.
inline GlTexture make_texture(GLenum target) {
  GLuint name = 0;
  glCreateTextures(target, 1, &name);
  return GlTexture(name);
}

}  // namespace sdm
