#pragma once
/// @file gl_context.h
/// An offscreen OpenGL 4.5 core context, created with OSMesa (default) or EGL (on a GPU through the EGL
/// device platform when there is one, else Mesa's surfaceless platform; `--gl-device N` picks a device:
/// preprocess/gl/egl_devices.h). Rendering goes to framebuffer objects; the context has no
/// window surface of its own. GL functions are loaded with glad (<glad/gl.h>) when the first context of
/// the process is created.
///
/// An EGL display (surfaceless or device platform) is initialised by the first EGL context on it and kept
/// until exit: terminating it would unload Mesa's driver while contexts of other threads may live.
///
/// Threads: create one context per worker thread. Contexts may be created, made current and destroyed
/// concurrently on different threads; a context must not be current on two threads at once.
/// Before the first context is created, LP_NUM_THREADS=0 is set unless already in the environment:
/// llvmpipe then rasterises in the calling thread, which was measured fastest with one worker per core.
#include <memory>
#include <string>

#include "preprocess/gl/egl_devices.h"

namespace firstshot {

enum class GLBackend { OSMesa, EGL };

/// "osmesa" | "egl" → GLBackend; @throws std::invalid_argument otherwise.
GLBackend parseGLBackend(const std::string& name);
const char* toString(GLBackend backend);

class GLContext {
 public:
  /// Creates the context and makes it current on the calling thread.
  /// @param eglDevice  EGL only: kEglDeviceProcess (the process-wide choice, setEglDevice), kEglDeviceAuto
  ///                   or a device index (preprocess/gl/egl_devices.h)
  /// @throws std::runtime_error naming the back end when it is unavailable or lacks OpenGL 4.5 core;
  ///         InputError for an EGL device index out of range.
  explicit GLContext(GLBackend backend = GLBackend::OSMesa, int eglDevice = kEglDeviceProcess);
  ~GLContext();
  GLContext(const GLContext&) = delete;
  GLContext& operator=(const GLContext&) = delete;

  /// Makes the context current on the calling thread (cheap if it already is).
  void makeCurrent();
  /// Releases it from the calling thread if current there.
  void release();
  GLBackend backend() const;
  /// GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  std::string description() const;
  /// GL_RENDERER alone, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" or "NVIDIA H100 80GB HBM3/PCIe/SSE2".
  std::string renderer() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace firstshot
