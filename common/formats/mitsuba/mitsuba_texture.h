#pragma once
/// @file mitsuba_texture.h
/// Mitsuba `<texture>` plugins as the project's textures (common/materials/texture.h): `bitmap` (its image read through
/// OpenImageIO, sRGB-decoded unless `raw` or `gamma` say otherwise, with its filter, wrap modes and uv transform) and
/// `checkerboard` (a 2 × 2 image looked up nearest, which is the checkerboard exactly). docs/scene-format.md,
/// "Mitsuba 3 XML scenes", states each mapping.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "common/formats/mitsuba/mitsuba_xml.h"
#include "common/materials/texture.h"

namespace firstshot::mitsuba {

/// A colour that may vary over a surface: the factor times the texture at each point (the factor alone without one).
struct TexturedColor {
  Color factor{1.0f};
  std::shared_ptr<const Texture> texture;  ///< null: constant
  /// The mean over the image (factor × the image's mean texel), the factor alone when constant.
  Color mean() const { return texture ? factor * texture->image->mean : factor; }
};

/// @p t with each texel c replaced by @p f(c) (a new image; the filter, wrap modes and transform kept, the alpha
/// channel dropped): a factor or a blend baked into the texels.
std::shared_ptr<const Texture> mapTexels(const Texture& t, const std::function<Color(const Color&)>& f);

/// Finds a file named in the scene (relative to the scene's folder, then to its `<path>` folders).
using FileResolver = std::function<std::filesystem::path(const std::string&)>;

/// Reads the textures of one document, each image file once per decoding.
class TextureMapper {
 public:
  TextureMapper(Document& doc, FileResolver resolve) : doc_(doc), resolve_(std::move(resolve)) {}

  /// The property @p name of @p p as a colour that may vary: a bitmap or checkerboard `<texture>` (nested or by
  /// `<ref>`) as a texture of factor 1, any other value as Plugin::color (@p fallback when absent).
  /// @throws InputError naming the element for bad values or an image that cannot be read.
  TexturedColor color(Plugin& p, const char* name, const Color& fallback);
  /// The property @p name of @p p as a number (a texture or colour by its mean over the channels, as Mitsuba's
  /// scalar lookups average them), @p fallback when absent.
  double scalar(Plugin& p, const char* name, double fallback);
  /// The bitmap or checkerboard `<texture>` @p node as a texture (read once per element).
  std::shared_ptr<const Texture> texture(pugi::xml_node node);
  /// The bitmap or checkerboard @p node as an opacity: a texture whose alpha (Texture::alphaLookup) is the luminance
  /// of its colour, as Mitsuba's mask reads a texture (an image's own alpha channel is not what it reads).
  std::shared_ptr<const Texture> opacity(pugi::xml_node node);
  /// The mean colour of a bitmap `<texture>` @p node (its image's mean texel), for properties that take constants.
  Color mean(pugi::xml_node node) { return texture(node)->image->mean; }

 private:
  std::shared_ptr<const Texture> bitmap(Plugin& t);
  std::shared_ptr<const Texture> checkerboard(Plugin& t);
  /// `to_uv` (Mitsuba 3), or `uscale`, `vscale`, `uoffset`, `voffset` (Mitsuba 0.6), as the texture's transform.
  TextureTransform uvTransform(Plugin& t);

  Document& doc_;
  FileResolver resolve_;
  std::map<std::string, std::shared_ptr<const TexelImage>> images_;  ///< by path and decoding
  /// By element and use (0: colour, 1: opacity).
  std::map<std::pair<pugi::xml_node, int>, std::shared_ptr<const Texture>> textures_;
};

}  // namespace firstshot::mitsuba
