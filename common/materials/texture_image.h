#pragma once
/// @file texture_image.h
/// Texture images of imported assets: an 8-bit PNG or JPEG, embedded or from a file, decoded through libpng and
/// libjpeg directly (not OpenImageIO, whose Debian build loads 267 shared libraries at start-up:
/// docs/architecture.md, "Image files"), and its mean values: where the renderer does not look a texture up per
/// point (common/materials/texture.h), the importer folds its mean into the material's factors (docs/scene-format.md, "Asset files as scenes").
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "common/util/math.h"

namespace firstshot {

/// How texture coordinates outside [0, 1] fold back (the glTF sampler's wrapS / wrapT).
enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

/// A decoded image: 8 bits per channel, RGBA, rows from the top; read as linear values in [0, 1].
struct TextureImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  ///< width·height·4 bytes
  bool srgb = false;          ///< colour data: R, G, B are sRGB-encoded (alpha is always linear)

  /// Linear R, G, B, A of texel (@p x, @p y), each in [0, 1] (sRGB decoded when srgb).
  std::array<float, 4> texel(int x, int y) const;
  /// The mean linear R, G, B, A over all texels.
  std::array<float, 4> mean() const;
};

/// Texel index @p i folded into [0, @p n) by @p wrap (as the glTF sampler folds texture coordinates).
int64_t foldTexelIndex(int64_t i, int64_t n, TextureWrap wrap);

/// Linear value of the sRGB-encoded @p c ∈ [0, 1] (IEC 61966-2-1).
float srgbDecode(double c);
/// Linear value of the 8-bit sRGB-encoded @p v: srgbDecode(v / 255) from a table.
float srgbToLinear(uint8_t v);

/// Decodes a PNG or JPEG (told by its signature) of any bit depth and colour type (16 bits are cut to 8, grey and
/// palette images become RGB, a missing alpha is 1). Colour-space chunks are ignored, as glTF requires.
/// @p srgb marks colour data (base colour, emission); other data (metallic-roughness) stays as stored.
/// @throws InputError (no file or element) naming what is wrong.
TextureImage decodeTextureImage(std::string_view bytes, bool srgb);

/// A triangle of texture coordinates (u right, v down from the image's top-left corner, as in glTF) and the weight
/// of its mean, e.g. its area on the surface in m².
struct UvTriangle {
  std::array<Vec2d, 3> uv;
  double weight = 1;
};

/// The weighted mean of @p image over @p triangles: each triangle's mean over the texels whose centres it covers
/// (the texel at its centroid when it covers no centre), texel indices folded by @p wrapU / @p wrapV, weighted by
/// its weight. Falls back to the whole image's mean() when the triangles cover more than @p maxTexels texel
/// centres in all (e.g. coordinates tiled many times) or weigh nothing; @p wholeImage then says so.
std::array<float, 4> meanOverTriangles(const TextureImage& image, const std::vector<UvTriangle>& triangles,
                                       TextureWrap wrapU, TextureWrap wrapV, bool* wholeImage = nullptr,
                                       double maxTexels = double(1 << 26));

}  // namespace firstshot
