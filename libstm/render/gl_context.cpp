#include "libstm/render/gl_context.h"

#include "libstm/core/errors.h"

#include "libstm/render/shaders.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace sdm {
namespace {

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::string egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: {
      std::ostringstream s;
      s << "EGL error 0x" << std::hex << e;
      return s.str();
    }
  }
}

// eglTerminate is not reference counted and eglGetPlatformDisplay returns the same handle for the
// same device, so two GlContexts on one device share a display: terminate it with the last one.
std::mutex display_mutex;
std::map<EGLDisplay, int> display_users;

void release_display(EGLDisplay d) {
  std::lock_guard<std::mutex> lock(display_mutex);
  if (--display_users[d] <= 0) {
    display_users.erase(d);
    eglTerminate(d);
  }
}

struct Candidate {
  std::string name;
  EGLenum platform = 0;  // 0: eglGetDisplay(EGL_DEFAULT_DISPLAY)
  void* native = nullptr;
};

// Tries to get a GL >= 4.5 core context current with no surface on one display. On success fills
// display/context and returns ""; otherwise returns why not (and leaves nothing behind).
std::string try_display(const Candidate& c, EGLDisplay& display_out, EGLContext& context_out) {
  EGLDisplay d = EGL_NO_DISPLAY;
  if (c.platform) {
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) return "eglGetPlatformDisplayEXT is not available";
    d = get_platform_display(c.platform, c.native, nullptr);
  } else {
    d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  }
  if (d == EGL_NO_DISPLAY) return "no display (" + egl_error_name(eglGetError()) + ")";
  {
    std::lock_guard<std::mutex> lock(display_mutex);
    EGLint major = 0, minor = 0;
    if (display_users[d] == 0 && !eglInitialize(d, &major, &minor)) {
      display_users.erase(d);
      return "eglInitialize failed (" + egl_error_name(eglGetError()) + ")";
    }
    ++display_users[d];
  }
  auto fail = [&](const std::string& why) {
    release_display(d);
    return why;
  };
  const char* ext = eglQueryString(d, EGL_EXTENSIONS);
  if (!has_extension(ext, "EGL_KHR_surfaceless_context"))
    return fail("no EGL_KHR_surfaceless_context (cannot render without a surface)");
  if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API) failed: no desktop OpenGL");

  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(ext, "EGL_KHR_no_config_context")) {
    // Rendering goes to framebuffer objects, so any config that supports desktop GL will do;
    // pbuffer-capable ones first because device displays expose no window configs.
    const EGLint surface_types[] = {EGL_PBUFFER_BIT, EGL_DONT_CARE};
    EGLint count = 0;
    for (EGLint st : surface_types) {
      const EGLint attribs[] = {EGL_SURFACE_TYPE, st, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      if (eglChooseConfig(d, attribs, &config, 1, &count) && count > 0) break;
    }
    if (count <= 0) return fail("no EGL config with EGL_OPENGL_BIT");
  }
  const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext ctx = eglCreateContext(d, config, EGL_NO_CONTEXT, ctx_attribs);
  if (ctx == EGL_NO_CONTEXT)
    return fail("cannot create a GL 4.5 core context (" + egl_error_name(eglGetError()) + ")");
  if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
    const std::string e = egl_error_name(eglGetError());
    eglDestroyContext(d, ctx);
    return fail("eglMakeCurrent with no surface failed (" + e + ")");
  }
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45) {
    eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(d, ctx);
    return fail("context is GL " + std::to_string(major) + "." + std::to_string(minor) + ", below 4.5");
  }
  display_out = d;
  context_out = ctx;
  return "";
}

std::vector<Candidate> candidates(const std::string& only) {
  std::vector<Candidate> hardware, software, result;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const bool want_device = only.empty() || only == "device";
  if (want_device && (has_extension(client, "EGL_EXT_device_enumeration") || has_extension(client, "EGL_EXT_device_base")) &&
      has_extension(client, "EGL_EXT_platform_device")) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint n = 0;
    if (query_devices && query_devices(0, nullptr, &n) && n > 0) {
      std::vector<EGLDeviceEXT> devices(n);
      query_devices(n, devices.data(), &n);
      for (EGLint i = 0; i < n; ++i) {
        const char* dext = query_string ? query_string(devices[i], EGL_EXTENSIONS) : nullptr;
        std::string name = "EGL device " + std::to_string(i);
        if (query_string && has_extension(dext, "EGL_EXT_device_drm"))
          if (const char* file = query_string(devices[i], EGL_DRM_DEVICE_FILE_EXT)) name += std::string(" (") + file + ")";
        const bool sw = has_extension(dext, "EGL_MESA_device_software");
        if (sw) name += " (software)";
        (sw ? software : hardware).push_back({name, EGL_PLATFORM_DEVICE_EXT, devices[i]});
      }
    }
  }
  result = hardware;
  if ((only.empty() || only == "surfaceless") && has_extension(client, "EGL_MESA_platform_surfaceless"))
    result.push_back({"Mesa surfaceless platform", EGL_PLATFORM_SURFACELESS_MESA, nullptr});
  result.insert(result.end(), software.begin(), software.end());
  if (only.empty() || only == "default") result.push_back({"default EGL display", 0, nullptr});
  if (!result.empty() && !has_extension(client, "EGL_EXT_platform_device") &&
      !has_extension(client, "EGL_MESA_platform_surfaceless"))
    result.front().name += " (EGL offers neither EGL_EXT_platform_device nor EGL_MESA_platform_surfaceless: "
                           "is an EGL vendor library installed?)";
  return result;
}

}  // namespace

GlContext::GlContext() {
  const char* env = std::getenv("SDM_EGL_PLATFORM");
  const std::string only = env ? env : "";
  if (!only.empty() && only != "device" && only != "surfaceless" && only != "default")
    throw std::runtime_error("SDM_EGL_PLATFORM='" + only + "' is not one of device, surfaceless, default");
  std::string tried;
  for (const Candidate& c : candidates(only)) {
    EGLDisplay d = EGL_NO_DISPLAY;
    EGLContext ctx = EGL_NO_CONTEXT;
    const std::string why = try_display(c, d, ctx);
    if (why.empty()) {
      display_ = d;
      context_ = ctx;
      platform_ = c.name;
      break;
    }
    tried += "\n  " + c.name + ": " + why;
  }
  if (!context_) {
    if (tried.empty()) tried = "\n  (EGL offers no device, no surfaceless platform and no default display)";
    throw std::runtime_error(
        "cannot create a headless OpenGL 4.5 core context through EGL. Tried:" + tried +
        "\nFix: install Mesa's EGL and GL drivers (Debian/Ubuntu: apt-get install libegl-mesa0 libgl1-mesa-dri), "
        "which give a software renderer (llvmpipe) everywhere; on an NVIDIA GPU install the driver's EGL library "
        "(libnvidia-egl / the full driver, not only the compute part).");
  }
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  renderer_ = str(GL_RENDERER);
  version_ = str(GL_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &major_);
  glGetIntegerv(GL_MINOR_VERSION, &minor_);
}

GlContext::~GlContext() {
  if (!context_) return;
  if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);  // frees the cached programs with it
  release_display(display_);
}

void GlContext::make_current() {
  if (eglGetCurrentContext() == context_) return;
  if (!eglBindAPI(EGL_OPENGL_API) || !eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw std::runtime_error("eglMakeCurrent failed (" + egl_error_name(eglGetError()) + ")");
}

bool GlContext::software() const {
  for (const char* s : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
    if (renderer_.find(s) != std::string::npos) return true;
  return false;
}

unsigned GlContext::program(const std::string& vertex_shader, const std::string& fragment_shader,
                            const std::string& geometry_shader) {
  make_current();
  const std::array<std::string, 3> key = {vertex_shader, fragment_shader, geometry_shader};
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second;
  const unsigned p = link_program(shader_source(vertex_shader), shader_source(fragment_shader),
                                  vertex_shader + " + " + (geometry_shader.empty() ? "" : geometry_shader + " + ") +
                                      fragment_shader,
                                  geometry_shader.empty() ? nullptr : shader_source(geometry_shader));
  programs_[key] = p;
  return p;
}

namespace {
GLuint compile(GLenum type, const char* source, const std::string& label) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &n);
    std::string log(std::max(n, 1), '\0');
    glGetShaderInfoLog(s, n, nullptr, &log[0]);
    glDeleteShader(s);
    const char* stage = type == GL_VERTEX_SHADER ? "vertex" : type == GL_GEOMETRY_SHADER ? "geometry" : "fragment";
    throw std::runtime_error("cannot compile " + std::string(stage) + " shader of " + label + ":\n" + log.c_str());
  }
  return s;
}
}  // namespace

unsigned link_program(const char* vertex_source, const char* fragment_source, const std::string& label,
                      const char* geometry_source) {
  std::vector<GLuint> stages;
  try {
    stages.push_back(compile(GL_VERTEX_SHADER, vertex_source, label));
    if (geometry_source) stages.push_back(compile(GL_GEOMETRY_SHADER, geometry_source, label));
    stages.push_back(compile(GL_FRAGMENT_SHADER, fragment_source, label));
  } catch (...) {
    for (GLuint s : stages) glDeleteShader(s);
    throw;
  }
  GLuint p = glCreateProgram();
  for (GLuint s : stages) glAttachShader(p, s);
  glLinkProgram(p);
  for (GLuint s : stages) glDeleteShader(s);  // flagged; freed with the program
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &n);
    std::string log(std::max(n, 1), '\0');
    glGetProgramInfoLog(p, n, nullptr, &log[0]);
    glDeleteProgram(p);
    throw std::runtime_error("cannot link program " + label + ":\n" + log.c_str());
  }
  return p;
}

void check_gl(const char* where) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  std::ostringstream s;
  s << "OpenGL error 0x" << std::hex << e << " in " << where;
  while (glGetError() != GL_NO_ERROR) {
  }
  throw std::runtime_error(s.str());
}

// ---------------------------------------------------------------------------------------------

Framebuffer::Framebuffer(int width, int height, int samples, bool float_attachment)
    : width_(width), height_(height), samples_(std::max(1, samples)), has_float_(float_attachment) {
  if (width <= 0 || height <= 0) throw std::runtime_error("Framebuffer: size must be positive");
  GLint max_size = 0, max_texture = 0, max_samples = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  max_size = std::min(max_size, max_texture);  // the colour attachments are textures
  if (width > max_size || height > max_size)
    throw InputError("an image of " + std::to_string(width) + "x" + std::to_string(height) + " exceeds this GL's limit of " +
                     std::to_string(max_size) + " pixels a side: use a smaller --width/--height");
  samples_ = std::min(samples_, std::max(1, int(max_samples)));

  auto make_texture = [&](GLenum format) {
    GLuint t = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, 1, format, width, height);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  };
  color_tex_ = make_texture(GL_RGBA8);
  if (has_float_) float_tex_ = make_texture(GL_RGBA32F);
  glCreateFramebuffers(1, &resolve_fbo_);
  glNamedFramebufferTexture(resolve_fbo_, GL_COLOR_ATTACHMENT0, color_tex_, 0);
  if (has_float_) glNamedFramebufferTexture(resolve_fbo_, GL_COLOR_ATTACHMENT1, float_tex_, 0);

  auto make_rb = [&](GLenum format) {
    GLuint r = 0;
    glCreateRenderbuffers(1, &r);
    glNamedRenderbufferStorageMultisample(r, samples_ > 1 ? samples_ : 0, format, width, height);
    return r;
  };
  depth_ = make_rb(GL_DEPTH_COMPONENT24);
  if (samples_ > 1) {
    glCreateFramebuffers(1, &draw_fbo_);
    ms_color_ = make_rb(GL_RGBA8);
    glNamedFramebufferRenderbuffer(draw_fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_color_);
    if (has_float_) {
      ms_float_ = make_rb(GL_RGBA32F);
      glNamedFramebufferRenderbuffer(draw_fbo_, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, ms_float_);
    }
    glNamedFramebufferRenderbuffer(draw_fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  } else {
    // Single-sampled: draw straight into the result textures.
    draw_fbo_ = resolve_fbo_;
    glNamedFramebufferRenderbuffer(draw_fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  }
  const GLenum status = glCheckNamedFramebufferStatus(draw_fbo_, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    std::ostringstream s;
    s << "Framebuffer: incomplete (status 0x" << std::hex << status << ") at " << std::dec << width << "x" << height
      << ": the GL could not allocate it; use a smaller --width/--height";
    throw std::runtime_error(s.str());
  }
  check_gl("Framebuffer");
}

Framebuffer::~Framebuffer() {
  if (draw_fbo_ != resolve_fbo_) glDeleteFramebuffers(1, &draw_fbo_);
  glDeleteFramebuffers(1, &resolve_fbo_);
  const GLuint rbs[] = {ms_color_, ms_float_, depth_};
  glDeleteRenderbuffers(3, rbs);
  const GLuint texs[] = {color_tex_, float_tex_};
  glDeleteTextures(2, texs);
}

void Framebuffer::bind() {
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_);
  const GLenum bufs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(has_float_ ? 2 : 1, bufs);
  glViewport(0, 0, width_, height_);
}

void Framebuffer::clear(const float rgba[4], const float float_value[4]) {
  static const float zero[4] = {0, 0, 0, 0};
  static const float one = 1.f;
  glClearNamedFramebufferfv(draw_fbo_, GL_COLOR, 0, rgba);
  if (has_float_) glClearNamedFramebufferfv(draw_fbo_, GL_COLOR, 1, float_value ? float_value : zero);
  glClearNamedFramebufferfv(draw_fbo_, GL_DEPTH, 0, &one);
}

void Framebuffer::resolve() {
  if (samples_ <= 1) return;
  const int n = has_float_ ? 2 : 1;
  for (int i = 0; i < n; ++i) {
    glNamedFramebufferReadBuffer(draw_fbo_, GL_COLOR_ATTACHMENT0 + i);
    glNamedFramebufferDrawBuffer(resolve_fbo_, GL_COLOR_ATTACHMENT0 + i);
    glBlitNamedFramebuffer(draw_fbo_, resolve_fbo_, 0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
  }
  check_gl("Framebuffer::resolve");
}

namespace {
template <class T>
void flip_rows(std::vector<T>& pixels, size_t row) {
  const size_t h = pixels.size() / row;
  for (size_t y = 0; y < h / 2; ++y)
    std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row, pixels.begin() + (h - 1 - y) * row);
}
}  // namespace

Image Framebuffer::read_rgba8() {
  resolve();
  Image img(width_, height_, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(color_tex_, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(img.pixels.size()), img.pixels.data());
  check_gl("Framebuffer::read_rgba8");
  flip_rows(img.pixels, size_t(width_) * 4);  // GL's first row is the bottom one
  return img;
}

FloatImage Framebuffer::read_float() {
  if (!has_float_) throw std::runtime_error("Framebuffer::read_float: made without a float attachment");
  resolve();
  FloatImage img(width_, height_, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(float_tex_, 0, GL_RGBA, GL_FLOAT, GLsizei(img.pixels.size() * sizeof(float)), img.pixels.data());
  check_gl("Framebuffer::read_float");
  flip_rows(img.pixels, size_t(width_) * 4);
  return img;
}

unsigned Framebuffer::color_texture() {
  resolve();
  return color_tex_;
}

unsigned Framebuffer::float_texture() {
  if (!has_float_) throw std::runtime_error("Framebuffer::float_texture: made without a float attachment");
  resolve();
  return float_tex_;
}

GLuint upload_texture(const Image& img, bool repeat, bool keep_alpha) {
  if (img.width <= 0 || img.height <= 0 || img.channels < 1 || img.channels > 4 ||
      img.pixels.size() != size_t(img.width) * img.height * img.channels)
    throw InputError("texture image is empty or inconsistent");
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (img.width > max_size || img.height > max_size)
    throw InputError("texture of " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                     " exceeds the GL limit of " + std::to_string(max_size));
  std::vector<uint8_t> rgba(size_t(img.width) * img.height * 4);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* s = img.at(x, img.height - 1 - y);
      uint8_t* d = &rgba[(size_t(y) * img.width + x) * 4];
      for (int k = 0; k < 3; ++k) d[k] = s[img.channels >= 3 ? k : 0];
      d[3] = !keep_alpha ? 255 : img.channels == 4 ? s[3] : img.channels == 2 ? s[1] : 255;
    }
  int levels = 1;
  while ((std::max(img.width, img.height) >> levels) > 0) ++levels;
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, levels, GL_RGBA8, img.width, img.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(t, 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glGenerateTextureMipmap(t);
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  const GLint wrap = repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, wrap);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, wrap);
  return t;
}

}  // namespace sdm
