#include "preprocess/gl/gl_context.h"

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

#include "preprocess/gl/egl_devices.h"

namespace firstshot {

namespace {

std::mutex gMutex;        // guards everything below that is process-wide
bool gGladLoaded = false; // glad's function pointers are process-wide; loaded once

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

GLADapiproc osmesaLoader(const char* name) { return reinterpret_cast<GLADapiproc>(OSMesaGetProcAddress(name)); }
GLADapiproc eglLoader(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }

}  // namespace

struct GLContext::Impl {
  GLBackend backend = GLBackend::OSMesa;
  OSMesaContext osmesa = nullptr;
  unsigned char osmesaPixel[4] = {0, 0, 0, 0};  // 1×1 default framebuffer; rendering uses FBOs
  EGLDisplay eglDisplay = EGL_NO_DISPLAY;
  EGLContext egl = EGL_NO_CONTEXT;
  std::string eglPlatform;  // "surfaceless" or "device N"
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

GLContext::GLContext(GLBackend backend, int eglDevice) : impl_(std::make_unique<Impl>()) {
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
    const EglDisplayHandle& display = eglDisplay(eglDevice);  // egl_devices.h: which device
    impl_->eglDisplay = display.display;
    impl_->eglPlatform = display.platform;
    auto cleanup = [&](const std::string& msg) {
      if (impl_->egl != EGL_NO_CONTEXT) eglDestroyContext(impl_->eglDisplay, impl_->egl);
      fail(backend, msg);
    };
    if (!eglBindAPI(EGL_OPENGL_API)) cleanup("eglBindAPI(EGL_OPENGL_API) failed");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasEglExtension(eglQueryString(impl_->eglDisplay, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
      const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(impl_->eglDisplay, want, &config, 1, &n) || n < 1) cleanup("no OpenGL EGLConfig");
    }
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    impl_->egl = eglCreateContext(impl_->eglDisplay, config, EGL_NO_CONTEXT, ctxAttribs);
    if (impl_->egl == EGL_NO_CONTEXT)
      cleanup(std::string("eglCreateContext (4.5 core) failed: ") + eglErrorName(eglGetError()) + " on the " +
              impl_->eglPlatform + (impl_->eglPlatform == "surfaceless" ? " platform" : ""));
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

std::string GLContext::renderer() const {
  const_cast<GLContext*>(this)->makeCurrent();
  const GLubyte* s = glGetString(GL_RENDERER);
  return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
}

}  // namespace firstshot
