#include "preprocess/gl/gl_device_option.h"

#include <fmt/core.h>

#include <charconv>
#include <stdexcept>

#include "common/util/error.h"
#include "preprocess/gl/gl_context.h"

namespace firstshot {

bool applyGLDeviceOption(const std::string& value, std::string& gl, bool glGiven) {
  if (value == "list") {
    printGLDevices(stdout);
    return true;
  }
  if (glGiven && gl != "egl")
    throw InputError("", "--gl-device", "chooses an EGL device: give --gl egl (or leave --gl out), not --gl " + gl);
  gl = "egl";
  if (value == "auto") {
    setEglDevice(kEglDeviceAuto);
    return false;
  }
  int n = -1;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
  if (ec != std::errc() || end != value.data() + value.size() || n < 0)
    throw InputError("", "--gl-device", "'" + value + "' is not a device number (0, 1, ...), auto or list");
  setEglDevice(n);  // InputError naming the count if out of range
  return false;
}

void printGLDevices(std::FILE* out) {
  const std::vector<EglDeviceInfo> devices = listEglDevices();
  fmt::print(out, "EGL devices (EGL_EXT_device_enumeration): {}\n", devices.size());
  for (const EglDeviceInfo& d : devices) {
    std::string gl;
    try {
      gl = GLContext(GLBackend::EGL, d.index).description();
    } catch (const std::exception& e) {
      gl = std::string("no OpenGL 4.5 core context: ") + e.what();
    }
    fmt::print(out, "  {}: {} [{}{}{}]\n", d.index, gl, d.software ? "software" : "GPU",
               d.name.empty() || d.name == d.drmFile ? "" : "; EGL: " + d.name, d.drmFile.empty() ? "" : "; " + d.drmFile);
  }
  try {
    const GLContext chosen(GLBackend::EGL, kEglDeviceAuto);
    fmt::print(out, "--gl egl without --gl-device: {} ({})\n", eglDisplay(kEglDeviceAuto).platform, chosen.description());
  } catch (const std::exception& e) {
    fmt::print(out, "--gl egl without --gl-device: none ({})\n", e.what());
  }
}

}  // namespace firstshot
