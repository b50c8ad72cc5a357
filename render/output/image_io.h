// Image files: OpenEXR (float, any channels) and PNG (8-bit RGB), written atomically and read back.
//
// The renderer writes exactly these two formats, so it links OpenEXR and libpng directly rather than an image
// library with every format built in (docs/architecture.md, "Image files": that cost 0.3 s of start-up per run).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace firstshot::image {

/// Writes a ZIP-compressed float OpenEXR image through a temporary file.
/// @param data  width × height × channels.size() floats, interleaved, top row first.
/// @throws std::runtime_error naming @p path when the file cannot be written.
void writeExr(const std::string& path, int width, int height, const std::vector<std::string>& channels,
              const float* data);

/// Writes an 8-bit RGB PNG (sRGB-encoded values as given) through a temporary file.
/// @param rgb  width × height × 3 bytes, top row first.
void writePng(const std::string& path, int width, int height, const uint8_t* rgb);

/// A decoded image: floats interleaved by channel, top row first.
struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;  ///< EXR: R, G, B, A, Y first where present, then the rest by name; PNG: R, G, B(, A)
  std::vector<float> data;            ///< EXR values as stored; PNG bytes / 255 (no transfer curve undone)
};

/// Reads an OpenEXR or PNG file (chosen by its signature, not its name).
/// @throws InputError naming @p path when it is missing, not one of the two formats, or truncated.
Image read(const std::string& path);

}  // namespace firstshot::image
