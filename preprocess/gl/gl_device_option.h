#pragma once
/// @file gl_device_option.h
/// firstshot-preprocess's `--gl-device` option: which EGL device the GL item buffers run on.
#include <cstdio>
#include <string>

namespace firstshot {

/// Applies `--gl-device VALUE`: "auto" (a GPU if EGL lists one, else Mesa's surfaceless platform), an index N
/// of EGL's devices (setEglDevice, preprocess/gl/egl_devices.h), or "list" (prints them, see printGLDevices).
/// A device implies `--gl egl`: sets @p gl to "egl", unless @p glGiven (the command line named `--gl`) with
/// another value.
/// @return true for "list" (printed: the caller exits 0)
/// @throws InputError (element "--gl-device") for another value, an index out of range (naming the count), or
///         `--gl osmesa` given with it.
bool applyGLDeviceOption(const std::string& value, std::string& gl, bool glGiven);

/// Prints one line per EGL device (index, GL_RENDERER of a context on it or why none opens, EGL's name, DRM
/// file, software or GPU) and the device `--gl egl` picks by itself, to @p out.
void printGLDevices(std::FILE* out);

}  // namespace firstshot
