#pragma once
/// @file egl_devices.h
/// The EGL displays behind GLContext's EGL back end: which device they run on.
///
/// EGL_EXT_device_enumeration lists the devices of every vendor library (with GLVND: NVIDIA's and Mesa's);
/// EGL_EXT_platform_device opens a display on one of them. The automatic choice (kEglDeviceAuto, what
/// `--gl egl` does without `--gl-device`) takes the first device that is not one of Mesa's software devices
/// (EGL_MESA_device_software), i.e. a GPU; without one, Mesa's surfaceless platform (llvmpipe, or Mesa's
/// GPU driver where /dev/dri has one); failing that, the first device that opens. `--gl-device N` takes
/// device N, whatever it is.
///
/// A display, once initialised, is kept until exit (terminating it would unload the driver while
/// contexts of other threads may live).
#include <string>
#include <vector>

namespace firstshot {

/// One device that EGL_EXT_device_enumeration lists; `--gl-device N` picks the one at index N.
struct EglDeviceInfo {
  int index = 0;
  std::string name;       ///< EGL_RENDERER_EXT (EGL_EXT_device_query_name), else the DRM file, else empty
  std::string drmFile;    ///< EGL_DRM_DEVICE_FILE_EXT (EGL_EXT_device_drm); empty without
  std::string extensions; ///< the device's extension string (EGL_EXT_device_query)
  bool software = false;  ///< EGL_MESA_device_software: Mesa's CPU rasteriser
};

/// The devices EGL lists, in its order (at most 64); empty when the EGL library lacks
/// EGL_EXT_device_enumeration.
std::vector<EglDeviceInfo> listEglDevices();

inline constexpr int kEglDeviceAuto = -1;     ///< a GPU, else the surfaceless platform, else any device
inline constexpr int kEglDeviceProcess = -2;  ///< the process-wide choice (setEglDevice; auto until set)

/// Sets the device of the EGL contexts created with kEglDeviceProcess (GLContext's default): an index
/// into listEglDevices() or kEglDeviceAuto. Call before the first EGL context.
/// @throws InputError (element "--gl-device") naming the number of devices when @p device is not below it.
void setEglDevice(int device);

/// An initialised EGL display with EGL_KHR_surfaceless_context.
struct EglDisplayHandle {
  void* display = nullptr;  ///< the EGLDisplay
  std::string platform;     ///< "surfaceless" or "device N"
};

/// The display for @p device (kEglDeviceProcess, kEglDeviceAuto or an index), opened on first use and
/// kept until exit. Thread-safe.
/// @throws InputError as setEglDevice for an index out of range; std::runtime_error naming the
///         platforms tried when none opens.
const EglDisplayHandle& eglDisplay(int device);

/// True if @p glRenderer (a GL_RENDERER string) is one of Mesa's CPU rasterisers (llvmpipe, softpipe, swrast).
bool isSoftwareRenderer(const std::string& glRenderer);

/// True if the space-separated extension list @p list holds @p name (null list: false).
bool hasEglExtension(const char* list, const char* name);
/// The name of EGL error code @p error, e.g. "EGL_BAD_MATCH".
const char* eglErrorName(int error);

}  // namespace firstshot
