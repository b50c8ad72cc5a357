#pragma once
/// @file texture.h
/// Textures the renderer looks up at every hit: images read through OpenImageIO (PNG, JPEG, EXR and
/// whatever else it reads; 8- and 16-bit colour decoded from sRGB to linear, float data taken as linear), one
/// lookup on the full-resolution image, bilinear or nearest (the glTF sampler's filter, Mitsuba's filter_type), with
/// the glTF sampler's wrap modes and KHR_texture_transform.
///
/// No MIP maps, for now: every pixel of firstshot's images averages many samples (camera rays jittered over the
/// pixel), which supersamples the texture, so the bilinear lookup on level 0 converges to the box-filtered texture
/// without the blur a MIP level chosen from a footprint adds and without ray differentials along the paths.
/// Measured (docs/measurements.md, "Texture lookups"): where a texel covers about a pixel or more, the texture adds
/// no noise at 16 spp (Cornell, RMS 0.0628 against 0.0624 untextured); under strong minification (a 1-texel checker
/// tiled 8× on a floor seen at grazing angles) its aliasing is the noise (RMS 0.030 against 0.0022) and only falls
/// as 1/√spp. A MIP pyramid with camera-ray footprints would be the remedy for such scenes.
///
/// The images come through common/oiio/ (a module loaded on first use: only scenes with textures pay for
/// OpenImageIO's start-up). Imported assets' textures that are not looked up per point (on other coordinates than
/// TEXCOORD_0, transmission; an emitter's mean over its mesh) are decoded by common/materials/texture_image.h for their means.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "common/materials/texture_image.h"
#include "common/util/math.h"

namespace firstshot {

/// KHR_texture_transform: uv' = T(offset) · R(rotation) · S(scale) · uv, with glTF's rotation sense
/// (counter-clockwise in uv with v down, radians).
struct TextureTransform {
  Vec2 offset{0.0f};
  float rotation = 0.0f;  ///< radians
  Vec2 scale{1.0f};
  Vec2 apply(const Vec2& uv) const;
  bool isIdentity() const { return offset == Vec2(0.0f) && rotation == 0.0f && scale == Vec2(1.0f); }
};

/// A decoded image: linear RGB texels, rows from the top (texel (x, y) covers u ∈ [x/w, (x+1)/w],
/// v ∈ [y/h, (y+1)/h]).
struct TexelImage {
  int width = 0, height = 0;
  std::vector<Color> texels;  ///< width·height, row-major
  /// Linear alpha per texel (width·height, row-major), never sRGB-decoded; empty when the image has no alpha
  /// channel (cut-outs: Texture::alphaLookup).
  std::vector<float> alpha;
  Color mean{0.0f};           ///< mean of the texels
  std::string name;           ///< the file (or glTF image) it came from, for messages
  uint64_t hash = 0;          ///< of the texels and size (not the alpha)
  const Color& at(int x, int y) const { return texels[size_t(y) * size_t(width) + size_t(x)]; }
};

/// How a lookup between texel centres reads the image: linear interpolates the four nearest texels (bilinear), nearest
/// takes the texel the point lies in, so a texel's value holds over its whole square (glTF's NEAREST, Mitsuba's
/// filter_type "nearest": pixel art, checkers, label maps).
enum class TextureFilter : uint8_t { Linear, Nearest };

/// A texture as a material uses it: an image (shared between materials), its filter, wrap modes and transform.
struct Texture {
  std::shared_ptr<const TexelImage> image;
  TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;
  TextureFilter filter = TextureFilter::Linear;
  TextureTransform transform;

  /// The texture at texture coordinates @p uv (glTF convention), after the transform: bilinear between texel
  /// centres (exact at them), or the texel @p uv lies in (nearest); texel indices outside the image fold back by the
  /// wrap modes. Linear RGB.
  Color lookup(const Vec2& uv) const;
  /// The alpha at @p uv, looked up as lookup(): the image's alpha channel, or its first channel (R, or grey) when it
  /// has none.
  float alphaLookup(const Vec2& uv) const;
  /// A hash of the image, filter, wrap modes and transform (for scene hashes; the linear filter adds nothing, so
  /// textures read before filters existed keep their hashes).
  uint64_t hash() const;
};

/// Builds an image from linear RGB @p texels (width·height, rows from the top), e.g. for tests.
TexelImage makeTexelImage(int width, int height, std::vector<Color> texels, std::string name);

/// Reads an image file through OpenImageIO; integer data are sRGB-decoded when @p srgb. Grey becomes RGB;
/// an alpha channel is kept in TexelImage::alpha (linear). @throws InputError (no file or element) saying why.
TexelImage readTexelImage(const std::string& path, bool srgb);

/// Decodes an image held in memory (e.g. embedded in a .glb); @p name names it and its extension tells the
/// format when the bytes do not (PNG and JPEG are told by their signature). @throws InputError as readTexelImage.
TexelImage decodeTexelImage(std::string_view bytes, const std::string& name, bool srgb);

}  // namespace firstshot
