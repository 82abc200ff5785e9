#include "app/render/egl_context.hpp"

#include <EGL/eglext.h>
#include <GLES3/gl3.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <optional>
#include <string_view>

#include "drivers/platform/resident_libraries.hpp"

namespace probeless::render {
namespace {

std::string egl_failure(const char* call) {
  EGLint code = eglGetError();
  return fmt::format("{} failed: {} (0x{:04x})", call, egl_error_name(code), code);
}

bool has_word(const char* list, const char* word) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(word);
  for (const char* p = list; (p = std::strstr(p, word)) != nullptr; p += n) {
    const bool starts = p == list || p[-1] == ' ';
    const bool ends = p[n] == '\0' || p[n] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

// Mesa hands out one EGLDisplay per (platform, native display), and eglTerminate() ends it
// for every user in the process; several EglContexts (two renderers, successive tests) share
// it, so it is terminated only when the last one goes.
std::mutex display_users_mutex;
std::map<EGLDisplay, int> display_users;

void acquire_display(EGLDisplay d) {
  std::lock_guard lock(display_users_mutex);
  ++display_users[d];
}

void release_display(EGLDisplay d) {
  std::lock_guard lock(display_users_mutex);
  auto it = display_users.find(d);
  if (it == display_users.end() || --it->second > 0) return;
  display_users.erase(it);
  eglTerminate(d);
}

// Mesa's gallium driver keeps process-lifetime state in its own globals and never frees it
// (util_cpu_detect's L3 affinity masks, the 10 MB executable heap of rtasm), yet the last
// eglTerminate() dlclose()s the driver (drivers/platform/resident_libraries.hpp has the
// consequences). Mesa names the driver <name>_dri.so (up to 24.x; from 24.1 the code lives in
// libgallium-<version>.so, which a pinned *_dri.so keeps loaded too). Other vendors' EGL
// stacks match nothing here.
void keep_gl_drivers_loaded() {
  platform::keep_loaded_until_exit([](std::string_view path) {
    const std::string_view file = platform::file_name(path);
    return file.ends_with("_dri.so") || file.starts_with("libgallium");
  });
}

PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display_fn() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!has_word(client, "EGL_EXT_platform_base"))
    throw EglError("EGL: EGL_EXT_platform_base is missing (libEGL without platform support)");
  auto fn = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (fn == nullptr) throw EglError("EGL: eglGetPlatformDisplayEXT not found");
  return fn;
}

// The one place that turns a platform into an initialised display. Returns the display (with
// a user counted) or throws EglError saying why this platform cannot be used.
EGLDisplay open_display(EglPlatform platform) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_display = get_platform_display_fn();
  std::vector<EGLDisplay> candidates;
  switch (platform) {
    case EglPlatform::Surfaceless: {
      if (!has_word(client, "EGL_MESA_platform_surfaceless"))
        throw EglError("EGL_MESA_platform_surfaceless is not offered by libEGL");
      EGLDisplay d = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (d == EGL_NO_DISPLAY) throw EglError(egl_failure("eglGetPlatformDisplayEXT(surfaceless)"));
      candidates.push_back(d);
      break;
    }
    case EglPlatform::Device: {
      if (!has_word(client, "EGL_EXT_platform_device") ||
          !has_word(client, "EGL_EXT_device_enumeration"))
        throw EglError("EGL_EXT_platform_device / EGL_EXT_device_enumeration not offered");
      auto query_devices =
          reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
      if (query_devices == nullptr) throw EglError("eglQueryDevicesEXT not found");
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (!query_devices(16, devices, &count)) throw EglError(egl_failure("eglQueryDevicesEXT"));
      if (count == 0) throw EglError("eglQueryDevicesEXT found no EGL device");
      for (EGLint i = 0; i < count; ++i) {
        EGLDisplay d = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY) candidates.push_back(d);
      }
      break;
    }
  }
  std::string why;
  for (EGLDisplay d : candidates) {
    EGLint major = 0, minor = 0;
    if (eglInitialize(d, &major, &minor)) {
      keep_gl_drivers_loaded();
      acquire_display(d);
      return d;
    }
    why = egl_failure("eglInitialize");
  }
  throw EglError(why.empty() ? std::string("no display") : why);
}

EGLContext create_gles3_context(EGLDisplay display) {
  const char* ext = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_word(ext, "EGL_KHR_surfaceless_context"))
    throw EglError("display lacks EGL_KHR_surfaceless_context");
  if (!eglBindAPI(EGL_OPENGL_ES_API)) throw EglError(egl_failure("eglBindAPI(EGL_OPENGL_ES_API)"));
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_word(ext, "EGL_KHR_no_config_context")) {
    const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, config_attribs, &config, 1, &n) || n == 0)
      throw EglError("no EGLConfig renders OpenGL ES 3 (" + egl_failure("eglChooseConfig") + ")");
  }
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0,
                                    EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT) throw EglError(egl_failure("eglCreateContext(GLES 3.0)"));
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    std::string why = egl_failure("eglMakeCurrent(no surface)");
    eglDestroyContext(display, context);
    throw EglError(why);
  }
  return context;
}

std::optional<EglPlatform> platform_from_env() {
  const char* v = std::getenv("PROBELESS_EGL_PLATFORM");
  if (v == nullptr || *v == '\0') return std::nullopt;
  std::string s(v);
  if (s == "surfaceless") return EglPlatform::Surfaceless;
  if (s == "device") return EglPlatform::Device;
  throw EglError("PROBELESS_EGL_PLATFORM=" + s + ": expected 'surfaceless' or 'device'");
}

}  // namespace

const char* to_string(EglPlatform platform) {
  switch (platform) {
    case EglPlatform::Surfaceless:
      return "surfaceless";
    case EglPlatform::Device:
      return "device";
  }
  return "?";
}

std::vector<EglPlatform> default_egl_platforms() {
  if (auto forced = platform_from_env()) return {*forced};
  return {EglPlatform::Surfaceless, EglPlatform::Device};
}

const char* egl_error_name(EGLint code) {
  switch (code) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
      return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
      return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
      return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
      return "EGL_CONTEXT_LOST";
    case EGL_BAD_DEVICE_EXT:
      return "EGL_BAD_DEVICE_EXT";
    default:
      return "unknown EGL error";
  }
}

EglContext::EglContext(std::span<const EglPlatform> platforms)
    : owner_(std::this_thread::get_id()) {
  std::string attempts;
  for (EglPlatform p : platforms) {
    EGLDisplay display = EGL_NO_DISPLAY;
    try {
      display = open_display(p);
      context_ = create_gles3_context(display);
      display_ = display;
      platform_ = p;
      break;
    } catch (const EglError& e) {
      if (display != EGL_NO_DISPLAY) release_display(display);
      attempts += fmt::format("{}{}: {}", attempts.empty() ? "" : "; ", to_string(p), e.what());
    }
  }
  if (context_ == EGL_NO_CONTEXT)
    throw EglError("EGL: no headless OpenGL ES 3 context (" +
                   (attempts.empty() ? std::string("no platform to try") : attempts) + ")");

  auto gl_string = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s != nullptr ? s : "?");
  };
  renderer_ = gl_string(GL_RENDERER);
  gl_version_ = gl_string(GL_VERSION);
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i)
    gl_extensions_.emplace_back(
        reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i))));
  spdlog::info("render: EGL platform {}, GL_RENDERER {}, {}", to_string(platform_), renderer_,
               gl_version_);
}

EglContext::~EglContext() {
  if (eglGetCurrentContext() == context_)
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  release_display(display_);
}

void EglContext::make_current() {
  if (std::this_thread::get_id() != owner_)
    throw std::logic_error(
        "render: EGL context used on a thread other than the one that created it");
  if (eglGetCurrentContext() == context_) return;
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    throw EglError(egl_failure("eglMakeCurrent"));
}

bool EglContext::has_gl_extension(const char* name) const {
  return std::find(gl_extensions_.begin(), gl_extensions_.end(), name) != gl_extensions_.end();
}

}  // namespace probeless::render
