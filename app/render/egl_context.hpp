#pragma once
// A headless EGL display + OpenGL ES 3.0 context with no surface: the renderer draws into its
// own framebuffer objects and reads the pixels back.
//
// Threading: an EGL context is current on one thread at a time. EglContext makes its context
// current on the thread that constructs it, and every later use (including destruction) must
// happen on that same thread; the pipeline's processing thread creates the renderer and owns
// it (docs/architecture.md). make_current() checks this and throws instead of letting GL calls
// land in no context.
#include <EGL/egl.h>

#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace probeless::render {

// Where the display comes from. The choice lives here only. (The tethered display's EGL on
// GBM is not one of these: it has its own display, surface and thread, docs/display.md.)
enum class EglPlatform {
  Surfaceless,  // EGL_MESA_platform_surfaceless: GPU render node if any, else llvmpipe
  Device,       // EGL_EXT_platform_device: the first EGLDevice that initialises
};

const char* to_string(EglPlatform platform);

// The platforms tried, in order, when none is forced. PROBELESS_EGL_PLATFORM=surfaceless or
// =device in the environment forces one (for tests and for boards whose driver needs it).
std::vector<EglPlatform> default_egl_platforms();

// An EGL failure: the call that failed and eglGetError()'s name ("EGL_BAD_ALLOC").
class EglError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* egl_error_name(EGLint code);

class EglContext {
 public:
  // Opens the first platform of `platforms` that gives an initialised display and a GLES 3.0
  // context, makes the context current on this thread and logs the choice. Throws EglError
  // listing every attempt when none works.
  explicit EglContext(std::span<const EglPlatform> platforms);
  EglContext() : EglContext(default_egl_platforms()) {}
  ~EglContext();

  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;
  EglContext(EglContext&&) = delete;
  EglContext& operator=(EglContext&&) = delete;

  // Makes the context current if it is not; throws std::logic_error on another thread.
  void make_current();

  EglPlatform platform() const { return platform_; }
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& renderer() const { return renderer_; }
  const std::string& gl_version() const { return gl_version_; }
  bool has_gl_extension(const char* name) const;

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  EglPlatform platform_ = EglPlatform::Surfaceless;
  std::thread::id owner_;
  std::string renderer_;
  std::string gl_version_;
  std::vector<std::string> gl_extensions_;
};

}  // namespace probeless::render
