#include "preprocess/gl/egl_devices.h"

#define EGL_NO_X11
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>

#include "common/util/error.h"

namespace firstshot {

namespace {

std::mutex gEglMutex;                      // guards the two below
std::map<int, EglDisplayHandle> gOpened;   // by device index, kEglDeviceAuto for the automatic choice
int gProcessDevice = kEglDeviceAuto;       // setEglDevice

constexpr int kMaxEglDevices = 64;

/// The raw device handles, in EGL's order; empty without EGL_EXT_device_enumeration.
std::vector<EGLDeviceEXT> queryEglDevices() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (!query || !(hasEglExtension(client, "EGL_EXT_device_enumeration") || hasEglExtension(client, "EGL_EXT_device_base")))
    return {};
  EGLDeviceEXT devices[kMaxEglDevices];
  EGLint count = 0;
  if (!query(kMaxEglDevices, devices, &count) || count < 0) return {};
  return std::vector<EGLDeviceEXT>(devices, devices + count);
}

std::string deviceString(EGLDeviceEXT device, EGLint name) {
  auto query = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  const char* s = query ? query(device, name) : nullptr;
  if (!s) eglGetError();  // clear EGL_BAD_PARAMETER for a name the device does not know
  return s ? std::string(s) : std::string();
}

EglDeviceInfo describeDevice(EGLDeviceEXT device, int index) {
  EglDeviceInfo info;
  info.index = index;
  info.extensions = deviceString(device, EGL_EXTENSIONS);
  info.software = hasEglExtension(info.extensions.c_str(), "EGL_MESA_device_software");
  if (hasEglExtension(info.extensions.c_str(), "EGL_EXT_device_drm"))
    info.drmFile = deviceString(device, EGL_DRM_DEVICE_FILE_EXT);
  if (hasEglExtension(info.extensions.c_str(), "EGL_EXT_device_query_name"))
    info.name = deviceString(device, EGL_RENDERER_EXT);
  if (info.name.empty()) info.name = info.drmFile;
  return info;
}

[[noreturn]] void deviceOutOfRange(int device, size_t count) {
  throw InputError("", "--gl-device",
                   "device " + std::to_string(device) + " does not exist: EGL lists " + std::to_string(count) +
                       (count == 0 ? " devices (no EGL_EXT_device_enumeration, or no driver)"
                                   : count == 1 ? " device (0; --gl-device list shows it)"
                                                : " devices (0 to " + std::to_string(count - 1) + "; --gl-device list shows them)"));
}

/// Initialises @p d and checks it can make surfaceless contexts; on success stores it under @p key.
const EglDisplayHandle* tryOpenDisplay(EGLDisplay d, const std::string& platform, int key, std::string& errors) {
  if (d == EGL_NO_DISPLAY) {
    errors += platform + ": no display (" + eglErrorName(eglGetError()) + "); ";
    return nullptr;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(d, &major, &minor)) {
    errors += platform + ": eglInitialize failed (" + eglErrorName(eglGetError()) + "); ";
    return nullptr;
  }
  if (!hasEglExtension(eglQueryString(d, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
    errors += platform + ": no EGL_KHR_surfaceless_context; ";
    eglTerminate(d);
    return nullptr;
  }
  return &(gOpened[key] = EglDisplayHandle{d, platform});
}

/// Opens the display for @p key (kEglDeviceAuto or a device index). gEglMutex held.
const EglDisplayHandle& openDisplay(int key) {
  if (auto it = gOpened.find(key); it != gOpened.end()) return it->second;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto platformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!platformDisplay || !hasEglExtension(client, "EGL_EXT_platform_base"))
    throw std::runtime_error("OpenGL back end 'egl': no usable display (no EGL_EXT_platform_base)");
  const bool devicePlatform = hasEglExtension(client, "EGL_EXT_platform_device");
  const std::vector<EGLDeviceEXT> devices = queryEglDevices();
  auto onDevice = [&](size_t i, std::string& errors) {
    return tryOpenDisplay(platformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr), "device " + std::to_string(i), key, errors);
  };
  std::string errors;
  if (key >= 0) {
    if (size_t(key) >= devices.size()) deviceOutOfRange(key, devices.size());
    if (!devicePlatform) errors += "no EGL_EXT_platform_device; ";
    else if (const EglDisplayHandle* h = onDevice(size_t(key), errors)) return *h;
  } else {
    if (devicePlatform)  // a GPU first
      for (size_t i = 0; i < devices.size(); ++i)
        if (!describeDevice(devices[i], int(i)).software)
          if (const EglDisplayHandle* h = onDevice(i, errors)) return *h;
    if (hasEglExtension(client, "EGL_MESA_platform_surfaceless"))
      if (const EglDisplayHandle* h = tryOpenDisplay(platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                                              "surfaceless", key, errors))
        return *h;
    if (devicePlatform)  // then any device
      for (size_t i = 0; i < devices.size(); ++i)
        if (describeDevice(devices[i], int(i)).software)
          if (const EglDisplayHandle* h = onDevice(i, errors)) return *h;
    if (!devicePlatform) errors += "no EGL_EXT_platform_device; ";
    else if (devices.empty()) errors += "device: no EGL devices; ";
  }
  throw std::runtime_error("OpenGL back end 'egl': no usable display (" + errors + "set EGL_LOG_LEVEL=debug for details)");
}

}  // namespace

std::vector<EglDeviceInfo> listEglDevices() {
  std::lock_guard<std::mutex> lock(gEglMutex);
  const std::vector<EGLDeviceEXT> devices = queryEglDevices();
  std::vector<EglDeviceInfo> out;
  for (size_t i = 0; i < devices.size(); ++i) out.push_back(describeDevice(devices[i], int(i)));
  return out;
}

void setEglDevice(int device) {
  std::lock_guard<std::mutex> lock(gEglMutex);
  if (device >= 0) {
    const size_t count = queryEglDevices().size();
    if (size_t(device) >= count) deviceOutOfRange(device, count);
  }
  gProcessDevice = device < 0 ? kEglDeviceAuto : device;
}

const EglDisplayHandle& eglDisplay(int device) {
  std::lock_guard<std::mutex> lock(gEglMutex);
  return openDisplay(device == kEglDeviceProcess ? gProcessDevice : device < 0 ? kEglDeviceAuto : device);
}

bool isSoftwareRenderer(const std::string& glRenderer) {
  for (const char* s : {"llvmpipe", "softpipe", "swrast"})
    if (glRenderer.find(s) != std::string::npos) return true;
  return false;
}

bool hasEglExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

const char* eglErrorName(int e) {
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
    case EGL_BAD_DEVICE_EXT: return "EGL_BAD_DEVICE_EXT";
    default: return "EGL error";
  }
}

}  // namespace firstshot
