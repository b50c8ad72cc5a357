#include "preprocess/gl_context.h"

// glad first: it provides the GL types and keeps <GL/gl.h> (pulled in by osmesa.h) out.
#include <glad/gl.h>
#define EGL_NO_X11
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace fs {

namespace {

std::mutex gMutex;        // guards everything below that is process-wide
bool gGladLoaded = false; // glad's function pointers are process-wide; loaded once

/// One EGL display for the whole process (EGL displays are per process, eglTerminate kills all
/// contexts): initialised by the first EGL context and kept until exit. Terminating it would unload
/// Mesa's driver (dlclose), turning the driver's one-time allocations into unreachable "leaks".
struct EglDisplay {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
} gEgl;

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

[[noreturn]] void fail(GLBackend b, const std::string& message) {
  throw std::runtime_error(std::string("OpenGL back end '") + toString(b) + "': " + message);
}

/// Before the first context: llvmpipe rasterises in the calling thread (see gl_context.h).
void setLlvmpipeThreads() {
  static std::once_flag once;
  std::call_once(once, [] { setenv("LP_NUM_THREADS", "0", /*overwrite=*/0); });
}

/// Called with the new context current and gMutex held.
void loadGLFunctions(GLBackend b, GLADloadfunc loader) {
  if (!gGladLoaded) {
    if (gladLoadGL(loader) == 0) fail(b, "could not load the OpenGL functions (glad)");
    gGladLoaded = true;
  }
  // The pointers of either loader work for both back ends with Mesa: they all end in Mesa's per-thread
  // dispatch. Check the version of this context in any case.
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45)
    fail(b, "OpenGL 4.5 core is required, the context has " + std::to_string(major) + "." + std::to_string(minor));
}

const char* eglErrorName(EGLint e) {
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
    default: return "EGL error";
  }
}

/// Initialises @p d; on success keeps it in gEgl.
bool tryEglDisplay(EGLDisplay d, const char* platform, std::string& errors) {
  if (d == EGL_NO_DISPLAY) {
    errors += std::string(platform) + ": no display (" + eglErrorName(eglGetError()) + "); ";
    return false;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(d, &major, &minor)) {
    errors += std::string(platform) + ": eglInitialize failed (" + eglErrorName(eglGetError()) + "); ";
    return false;
  }
  const char* ext = eglQueryString(d, EGL_EXTENSIONS);
  if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
    errors += std::string(platform) + ": no EGL_KHR_surfaceless_context; ";
    eglTerminate(d);
    return false;
  }
  gEgl.display = d;
  gEgl.platform = platform;
  return true;
}

/// Opens the process-wide display: surfaceless platform first, then the device platform. gMutex held.
void openEglDisplay() {
  if (gEgl.display != EGL_NO_DISPLAY) return;
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  std::string errors;
  if (!getPlatformDisplay || !hasExtension(clientExt, "EGL_EXT_platform_base")) {
    errors = "no EGL_EXT_platform_base; ";
  } else {
    if (hasExtension(clientExt, "EGL_MESA_platform_surfaceless") &&
        tryEglDisplay(getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                      "surfaceless", errors))
      return;
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (hasExtension(clientExt, "EGL_EXT_platform_device") && queryDevices) {
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (queryDevices(16, devices, &count))
        for (EGLint i = 0; i < count; ++i)
          if (tryEglDisplay(getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr), "device", errors))
            return;
      if (count == 0) errors += "device: no EGL devices; ";
    } else {
      errors += "no EGL_EXT_platform_device; ";
    }
  }
  fail(GLBackend::EGL, "no usable display (" + errors + "set EGL_LOG_LEVEL=debug for details)");
}

GLADapiproc osmesaLoader(const char* name) { return reinterpret_cast<GLADapiproc>(OSMesaGetProcAddress(name)); }
GLADapiproc eglLoader(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }

}  // namespace

struct GLContext::Impl {
  GLBackend backend = GLBackend::OSMesa;
  OSMesaContext osmesa = nullptr;
  unsigned char osmesaPixel[4] = {0, 0, 0, 0};  // 1×1 default framebuffer; rendering uses FBOs
  EGLDisplay eglDisplay = EGL_NO_DISPLAY;
  EGLContext egl = EGL_NO_CONTEXT;
};

namespace {
thread_local const void* tCurrent = nullptr;  // which of our contexts is current on this thread
}

GLBackend parseGLBackend(const std::string& name) {
  if (name == "osmesa") return GLBackend::OSMesa;
  if (name == "egl") return GLBackend::EGL;
  throw std::invalid_argument("unknown OpenGL back end '" + name + "' (osmesa | egl)");
}

const char* toString(GLBackend backend) { return backend == GLBackend::OSMesa ? "osmesa" : "egl"; }

GLContext::GLContext(GLBackend backend) : impl_(std::make_unique<Impl>()) {
  impl_->backend = backend;
  setLlvmpipeThreads();
  std::lock_guard<std::mutex> lock(gMutex);
  if (backend == GLBackend::OSMesa) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                           OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    impl_->osmesa = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!impl_->osmesa) fail(backend, "OSMesaCreateContextAttribs failed (no OpenGL 4.5 core profile?)");
    if (!OSMesaMakeCurrent(impl_->osmesa, impl_->osmesaPixel, GL_UNSIGNED_BYTE, 1, 1)) {
      OSMesaDestroyContext(impl_->osmesa);
      fail(backend, "OSMesaMakeCurrent failed");
    }
  } else {
    openEglDisplay();
    impl_->eglDisplay = gEgl.display;
    auto cleanup = [&](const std::string& msg) {
      if (impl_->egl != EGL_NO_CONTEXT) eglDestroyContext(impl_->eglDisplay, impl_->egl);
      fail(backend, msg);
    };
    if (!eglBindAPI(EGL_OPENGL_API)) cleanup("eglBindAPI(EGL_OPENGL_API) failed");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(eglQueryString(impl_->eglDisplay, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
      const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(impl_->eglDisplay, want, &config, 1, &n) || n < 1) cleanup("no OpenGL EGLConfig");
    }
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    impl_->egl = eglCreateContext(impl_->eglDisplay, config, EGL_NO_CONTEXT, ctxAttribs);
    if (impl_->egl == EGL_NO_CONTEXT)
      cleanup(std::string("eglCreateContext (4.5 core) failed: ") + eglErrorName(eglGetError()) + " on the " +
              gEgl.platform + " platform");
    if (!eglMakeCurrent(impl_->eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->egl))
      cleanup(std::string("eglMakeCurrent failed: ") + eglErrorName(eglGetError()));
  }
  tCurrent = impl_.get();
  try {
    loadGLFunctions(backend, backend == GLBackend::OSMesa ? osmesaLoader : eglLoader);
  } catch (...) {
    release();
    if (impl_->osmesa) OSMesaDestroyContext(impl_->osmesa);
    if (impl_->egl != EGL_NO_CONTEXT) eglDestroyContext(impl_->eglDisplay, impl_->egl);
    throw;
  }
}

GLContext::~GLContext() {
  std::lock_guard<std::mutex> lock(gMutex);
  if (impl_->backend == GLBackend::OSMesa) {
    if (tCurrent == impl_.get()) {
      OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
      tCurrent = nullptr;
    }
    OSMesaDestroyContext(impl_->osmesa);
  } else {
    // EGL may still consider it current on this thread even if another context was bound since.
    if (tCurrent == impl_.get() || eglGetCurrentContext() == impl_->egl) {
      eglMakeCurrent(impl_->eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      tCurrent = nullptr;  // unbinding also clears Mesa's dispatch for any other context
    }
    eglDestroyContext(impl_->eglDisplay, impl_->egl);
    if (eglGetCurrentContext() == EGL_NO_CONTEXT) eglReleaseThread();  // frees EGL's per-thread state
  }
}

void GLContext::makeCurrent() {
  if (tCurrent == impl_.get()) return;
  bool ok;
  if (impl_->backend == GLBackend::OSMesa) {
    ok = OSMesaMakeCurrent(impl_->osmesa, impl_->osmesaPixel, GL_UNSIGNED_BYTE, 1, 1);
  } else {
    ok = eglBindAPI(EGL_OPENGL_API) &&
         eglMakeCurrent(impl_->eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->egl);
  }
  if (!ok) fail(impl_->backend, "could not make the context current");
  tCurrent = impl_.get();
}

void GLContext::release() {
  if (tCurrent != impl_.get()) return;
  if (impl_->backend == GLBackend::OSMesa)
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  else
    eglMakeCurrent(impl_->eglDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  tCurrent = nullptr;
}

GLBackend GLContext::backend() const { return impl_->backend; }

std::string GLContext::description() const {
  const_cast<GLContext*>(this)->makeCurrent();
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return str(GL_RENDERER) + ", " + str(GL_VERSION);
}

}  // namespace fs
