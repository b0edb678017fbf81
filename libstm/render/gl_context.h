#pragma once
/// Headless OpenGL 4.5 core through EGL, with no window and no X server: the GPU through the EGL
/// device platform (what an NVIDIA driver offers headless), or Mesa's surfaceless platform, which
/// falls back to llvmpipe on a machine with no GPU. Plus the small GL helpers every renderer
/// needs: programs from embedded shaders and offscreen framebuffers with read-back.
///
/// GL objects belong to the context that was current when they were made; keep the GlContext
/// alive (and current on this thread) while using them. GL entry points are the prototypes of
/// <GL/glcorearb.h>, resolved by GLVND's libOpenGL: no loader is needed.
#include "libstm/core/image.h"

#include <array>
#include <map>
#include <string>
#include <utility>

namespace sdm {

class GlContext {
 public:
  /// Tries, in order: each hardware EGL device (EGL_EXT_device_enumeration + EGL_EXT_platform_device),
  /// Mesa's surfaceless platform, each software EGL device, the default display. The first one that
  /// gives a GL >= 4.5 core context, current with no surface, wins. The environment variable
  /// SDM_EGL_PLATFORM=device|surfaceless|default restricts the search to one kind.
  /// \throw std::runtime_error listing every attempt and how to fix the installation.
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  /// Makes this context current on the calling thread (EGL contexts are per thread).
  void make_current();

  const std::string& renderer() const { return renderer_; }  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  const std::string& version() const { return version_; }    // GL_VERSION
  const std::string& platform() const { return platform_; }  // which EGL path was taken
  int major_version() const { return major_; }
  int minor_version() const { return minor_; }
  bool software() const;  ///< llvmpipe / softpipe / swrast

  /// A linked program from embedded shaders (names of shaders/*.glsl; the geometry stage is
  /// optional), built once per context and cached: the context owns it. Throws
  /// std::runtime_error with the compiler or linker log.
  unsigned program(const std::string& vertex_shader, const std::string& fragment_shader,
                   const std::string& geometry_shader = "");

 private:
  void* display_ = nullptr;  ///< EGLDisplay
  void* context_ = nullptr;  ///< EGLContext
  std::string renderer_, version_, platform_;
  int major_ = 0, minor_ = 0;
  std::map<std::array<std::string, 3>, unsigned> programs_;
};

/// Compiles and links a program from GLSL source text; `label` names it in the error message.
/// \throw std::runtime_error with the info log on failure. A GL context must be current.
/// `geometry_source` may be null (no geometry stage).
unsigned link_program(const char* vertex_source, const char* fragment_source, const std::string& label,
                      const char* geometry_source = nullptr);

/// \throw std::runtime_error naming `where` when glGetError reports an error.
void check_gl(const char* where);

/// Uploads an image as a mipmapped RGBA8 texture with trilinear filtering, rows flipped so that
/// texture coordinate (0, 0) is the image's bottom-left corner (OBJ uv and atlas convention).
/// `repeat` wraps, otherwise clamps to the edge; without `keep_alpha` alpha is 255. Throws
/// InputError for an empty or inconsistent image or one larger than the GL limit. The caller owns
/// the texture (glDeleteTextures). Needs a current context.
unsigned upload_texture(const Image& img, bool repeat, bool keep_alpha);

/// An offscreen render target: RGBA8 colour (attachment 0), an optional RGBA32F attachment 1 (for
/// positions, displacement, coordinates), and a 24-bit depth buffer. With samples > 1 it renders
/// multisampled and resolves into single-sample textures before reading.
class Framebuffer {
 public:
  Framebuffer(int width, int height, int samples = 1, bool float_attachment = false);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  /// Binds for drawing, sets the viewport, and enables both draw buffers.
  void bind();
  /// Clears colour (RGBA8 attachment to `rgba`, float attachment to `float_value`, default 0) and
  /// depth; call after bind().
  void clear(const float rgba[4], const float float_value[4] = nullptr);

  /// Resolves (when multisampled) and reads back, rows top to bottom.
  Image read_rgba8();
  FloatImage read_float();

  /// Single-sample colour textures holding the resolved result, e.g. to texture a later pass.
  unsigned color_texture();
  unsigned float_texture();

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }
  bool has_float() const { return has_float_; }

 private:
  void resolve();
  int width_, height_, samples_;
  bool has_float_;
  unsigned draw_fbo_ = 0, resolve_fbo_ = 0;
  unsigned ms_color_ = 0, ms_float_ = 0, depth_ = 0;  ///< renderbuffers (multisampled) when samples > 1
  unsigned color_tex_ = 0, float_tex_ = 0;            ///< single-sample results
};

}  // namespace sdm
