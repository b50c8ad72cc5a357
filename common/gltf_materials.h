#pragma once
/// @file gltf_materials.h
/// glTF 2.0 metallic-roughness materials read from the asset's JSON (assimp 5.2 keeps the factors but not what the
/// textures mean, and drops KHR_materials_emissive_strength), and the conversion to firstshot's materials
/// (docs/scene-format.md, "Asset files as scenes"): the base-colour texture becomes the material's albedo texture
/// (common/texture.h); the metallic-roughness and emissive textures are still folded into constant factors.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/gltf_file.h"
#include "common/scene_desc.h"
#include "common/texture.h"
#include "common/texture_image.h"

namespace fs {

/// A material's use of a texture: textures[texture] (-1: none), read through TEXCOORD_<texCoord>.
struct GltfTextureRef {
  int64_t texture = -1;
  unsigned texCoord = 0;
  TextureTransform transform;  ///< KHR_texture_transform (its texCoord override included in texCoord)
};

/// materials[k] of a glTF file as the JSON gives it, absent values at the glTF 2.0 defaults.
struct GltfMaterial {
  Color baseColor{1.0f};    ///< pbrMetallicRoughness.baseColorFactor (RGB; alpha is not used)
  float metallic = 1.0f;    ///< pbrMetallicRoughness.metallicFactor
  float roughness = 1.0f;   ///< pbrMetallicRoughness.roughnessFactor
  Color emissive{0.0f};     ///< emissiveFactor × KHR_materials_emissive_strength, W/(m² sr)
  GltfTextureRef baseColorTexture, metallicRoughnessTexture, emissiveTexture;
};

/// Reads materials[@p k] of @p gltf (defaults where it is absent or malformed).
GltfMaterial readGltfMaterial(const nlohmann::json& gltf, size_t k);

/// The textures of one glTF file, each decoded once. A texture that cannot be read (missing or broken image,
/// an image type other than PNG and JPEG) is left out, as other renderers do: its factor is used alone, and
/// report() names it.
class GltfTextures {
 public:
  explicit GltfTextures(const GltfFile& file) : file_(file) {}
  /// The base-colour texture of @p ref (image read through OpenImageIO, sRGB decoded; sampler and transform), or
  /// nullptr when there is none or it cannot be read (then report() names it).
  std::shared_ptr<const Texture> texture(const GltfTextureRef& ref);
  /// The image of @p ref (sRGB decoded when @p srgb), or nullptr when there is none or it cannot be read.
  const TextureImage* image(const GltfTextureRef& ref, bool srgb);
  /// The sampler's wrap modes (u, v) of @p ref; repeat by default.
  std::pair<TextureWrap, TextureWrap> wrap(const GltfTextureRef& ref) const;
  /// Prints one line on stderr when textures could not be read: "F: N textures not read, their factors used
  /// alone (first: why)". @return the line, or "".
  std::string report(const std::string& file) const;

 private:
  const GltfFile& file_;
  std::map<std::pair<int64_t, bool>, std::optional<TextureImage>> images_;
  std::map<int64_t, std::shared_ptr<const TexelImage>> texels_;  ///< by texture, read once (null: failed)
  std::vector<std::string> failures_;
};

/// The material of a metallic-roughness surface (metallic m, roughness r, base colour b, F0 = 0.04): diffuse with
/// albedo b when m = 0 and r = 1, else a stretched-Phong glossy material,
///   albedo = b·(1−m)·(1−F0), specular = F0·(1−m) + b·m (their sum stays ≤ 1),
///   exponent n = 2/α² − 2 with α = r² (Walter et al. 2007's Phong–Beckmann match), clamped to [1, 10⁴].
MaterialDesc metallicRoughnessMaterial(const Color& base, float metallic, float roughness);

/// The material of @p g: its metallic-roughness texture folded in (metallic × the mean of the texture's B channel,
/// roughness × the mean of its G channel); its base-colour texture, when read through TEXCOORD_0, as the albedo
/// texture (albedo = the factor's diffuse part, the specular part tinted by factor × the texture's mean), else
/// folded in as its mean. Emission is g.emissive, without its texture (it depends on the mesh: emissionOnMesh).
MaterialDesc convertGltfMaterial(const GltfMaterial& g, GltfTextures& textures);

/// The emission of @p g on a mesh whose triangles cover @p uv (in TEXCOORD_<emissiveTexture.texCoord>, weighted
/// by their area in m²): g.emissive × the emissive texture's mean over those texels (meanOverTriangles). Without
/// such coordinates, or when the texture cannot be read: over the whole texture, or g.emissive alone.
Color emissionOnMesh(const GltfMaterial& g, GltfTextures& textures, const std::vector<UvTriangle>* uv);

}  // namespace fs
