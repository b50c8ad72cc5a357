#pragma once
/// @file read_image.h
/// The interface between common/materials/texture.cpp and the OpenImageIO module (libfirstshot_oiio.so, read_image.cpp),
/// which texture.cpp loads with dlopen the first time a scene has a texture: Debian's OpenImageIO brings 267
/// shared libraries and 0.2–0.4 s of start-up (docs/architecture.md, "Image files"), which only scenes with
/// textures should pay.
#include <cstddef>
#include <string>
#include <vector>

namespace firstshot {

/// An image as the module returns it: float pixels, rows from the top, channels interleaved.
struct ModuleImage {
  int width = 0, height = 0, channels = 0;
  bool integer = false;       ///< stored as integers (8 or 16 bits: sRGB-encoded colour), else floating point
  std::vector<float> pixels;  ///< width·height·channels values; integers scaled to [0, 1]
  std::string error;          ///< why the image could not be read ("" on success)
};

/// The module's one function, looked up by name (kReadImageSymbol): reads @p name, or the @p size bytes at
/// @p bytes when @p bytes is not null (then @p name is only a hint of the format, e.g. "image.png").
using ReadImageFn = void (*)(const char* name, const void* bytes, size_t size, ModuleImage* out);
inline constexpr const char* kReadImageSymbol = "firstshot_read_image";

}  // namespace firstshot
