#include "gl/device.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "gl/gl.h"

namespace pointnpr::gl {

namespace {

std::mutex g_instance_mutex;
std::unique_ptr<Device> g_instance;

std::string egl_error_name(EGLint code) {
  switch (code) {
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
    default: return "EGL error " + std::to_string(code);
  }
}

constexpr const char* kInstallHint =
    "PointNPR renders with its own headless OpenGL 4.5 core context through EGL. "
    "Install a GPU driver with EGL support, or Mesa's software renderer "
    "(Debian/Ubuntu: apt install libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0).";

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// Prefer a hardware EGL device (a real GPU), else Mesa's surfaceless platform.
EGLDisplay open_display(bool force_software, std::string& platform, std::vector<std::string>& failures) {
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!force_software && has_extension(client_ext, "EGL_EXT_device_enumeration")) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (query_devices && query_string && query_devices(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = query_string(devices[i], EGL_EXTENSIONS);
        if (has_extension(ext, "EGL_MESA_device_software")) continue;
        EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint major = 0, minor = 0;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
          platform = "device";
          return d;
        }
        failures.push_back("EGL device " + std::to_string(i) + ": " + egl_error_name(eglGetError()));
      }
    }
  }
  EGLDisplay d = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
    platform = "surfaceless";
    return d;
  }
  failures.push_back("Mesa surfaceless platform: " + egl_error_name(eglGetError()));
  return EGL_NO_DISPLAY;
}

}  // namespace

bool software_device_forced() {
  const char* value = std::getenv("POINTNPR_EGL_DEVICE");
  const std::string v = value ? value : "";
  if (v.empty() || v == "auto") return false;
  if (v == "software") return true;
  throw GLError("POINTNPR_EGL_DEVICE is '" + v +
                "'; accepted values: 'auto' (a GPU when EGL enumerates one, else Mesa's llvmpipe; the default) or "
                "'software' (Mesa's surfaceless llvmpipe only)");
}

std::string no_display_message(const std::vector<std::string>& failures, bool software_forced) {
  std::string tried;
  for (const std::string& f : failures) tried += (tried.empty() ? "" : "; ") + f;
  std::string msg = "no EGL display could be opened";
  if (!tried.empty()) msg += " (" + tried + ")";
  msg += ". ";
  msg += kInstallHint;
  msg += software_forced ? " POINTNPR_EGL_DEVICE=software is set, so only Mesa's surfaceless llvmpipe was tried; "
                           "unset it to try GPU devices too."
                         : " Set POINTNPR_EGL_DEVICE=software to force Mesa's surfaceless llvmpipe.";
  return msg;
}

namespace {

}  // namespace

Device& Device::instance() {
  std::lock_guard lock(g_instance_mutex);
  if (!g_instance) g_instance.reset(new Device());
  return *g_instance;
}

bool Device::exists() {
  std::lock_guard lock(g_instance_mutex);
  return g_instance != nullptr;
}

void Device::shutdown() {
  std::lock_guard lock(g_instance_mutex);
  g_instance.reset();
}

Device::Device() {
  std::promise<void> ready;
  auto started = ready.get_future();
  thread_ = std::thread(&Device::thread_main, this, std::move(ready));
  try {
    started.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

Device::~Device() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Device::post(std::function<void()> job) {
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  cv_.notify_one();
}

void Device::thread_main(std::promise<void> ready) {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  try {
    const bool forced = software_device_forced();
    std::vector<std::string> failures;
    display = open_display(forced, info_.egl_platform, failures);
    if (display == EGL_NO_DISPLAY) throw GLError(no_display_message(failures, forced));
    if (!eglBindAPI(EGL_OPENGL_API))
      throw GLError("EGL has no desktop OpenGL API (" + egl_error_name(eglGetError()) + "). " + kInstallHint);
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (context == EGL_NO_CONTEXT)
      throw GLError("could not create an OpenGL 4.5 core context (" + egl_error_name(eglGetError()) +
                    "; the driver needs EGL_KHR_no_config_context and GL 4.5). " + kInstallHint);
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
      throw GLError("could not make the OpenGL context current (" + egl_error_name(eglGetError()) + "). " +
                    kInstallHint);
    info_.vendor = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
    info_.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    info_.version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    info_.software = info_.renderer.find("llvmpipe") != std::string::npos ||
                     info_.renderer.find("softpipe") != std::string::npos;
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; ++i) {
      const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
      if (e && std::strcmp(e, "GL_NV_shader_atomic_int64") == 0) info_.int64_atomics = true;
    }
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &info_.max_texture_size);
    display_ = display;
    context_ = context;
    ready.set_value();
  } catch (...) {
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    if (display != EGL_NO_DISPLAY) eglTerminate(display);
    eglReleaseThread();
    ready.set_exception(std::current_exception());
    return;
  }

  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock lock(mutex_);
      cv_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) break;  // stopping and drained
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();  // packaged_task captures exceptions into the caller's future
  }
  eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, context);
  eglTerminate(display);
  eglReleaseThread();
}

void check_gl(const char* what) {
  GLenum err = glGetError();
  if (err == GL_NO_ERROR) return;
  std::string names;
  while (err != GL_NO_ERROR) {
    switch (err) {
      case GL_INVALID_ENUM: names += " GL_INVALID_ENUM"; break;
      case GL_INVALID_VALUE: names += " GL_INVALID_VALUE"; break;
      case GL_INVALID_OPERATION: names += " GL_INVALID_OPERATION"; break;
      case GL_INVALID_FRAMEBUFFER_OPERATION: names += " GL_INVALID_FRAMEBUFFER_OPERATION"; break;
      case GL_OUT_OF_MEMORY: names += " GL_OUT_OF_MEMORY"; break;
      default: names += " 0x" + std::to_string(err); break;
    }
    err = glGetError();
  }
  throw GLError(std::string("OpenGL error during ") + what + ":" + names);
}

}  // namespace pointnpr::gl
