#pragma once
/// @file gltf_materials.h
/// glTF 2.0 metallic-roughness materials read from the asset's JSON (assimp 5.2 keeps the factors but not what the
/// textures mean, and drops KHR_materials_emissive_strength), and the conversion to firstshot's materials
/// (docs/scene-format.md, "Asset files as scenes"): the base-colour texture becomes the material's albedo texture
/// (common/materials/texture.h); the metallic-roughness and emissive textures are still folded into constant factors.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/formats/assets/gltf_file.h"
#include "common/materials/texture.h"
#include "common/materials/texture_image.h"
#include "common/scene/scene_desc.h"

namespace firstshot {

/// A material's use of a texture: textures[texture] (-1: none), read through TEXCOORD_<texCoord>.
struct GltfTextureRef {
  int64_t texture = -1;
  unsigned texCoord = 0;
  TextureTransform transform;  ///< KHR_texture_transform (its texCoord override included in texCoord)
};

/// materials[k] of a glTF file as the JSON gives it, absent values at the glTF 2.0 defaults.
struct GltfMaterial {
  Color baseColor{1.0f};    ///< pbrMetallicRoughness.baseColorFactor (RGB; its alpha is `alpha` below)
  float metallic = 1.0f;    ///< pbrMetallicRoughness.metallicFactor
  float roughness = 1.0f;   ///< pbrMetallicRoughness.roughnessFactor
  Color emissive{0.0f};     ///< emissiveFactor × KHR_materials_emissive_strength, W/(m² sr)
  float ior = 1.5f;         ///< KHR_materials_ior's ior (1.5 without it; 0 stands for an infinite index)
  float transmission = 0.0f;  ///< KHR_materials_transmission's transmissionFactor
  bool volume = false;        ///< KHR_materials_volume with thicknessFactor > 0: a solid, not a thin wall
  GltfTextureRef baseColorTexture, metallicRoughnessTexture, emissiveTexture;
  GltfTextureRef transmissionTexture;  ///< its R channel multiplies transmission
  // Alpha (cut-outs): alphaMode, alphaCutoff and baseColorFactor's alpha.
  AlphaMode alphaMode = AlphaMode::Opaque;  ///< "OPAQUE" (default), "MASK", "BLEND"
  float alphaCutoff = 0.5f;                 ///< alphaCutoff (MASK)
  float alpha = 1.0f;                       ///< baseColorFactor[3]
  GltfTextureRef normalTexture;  ///< the tangent-space normal map
  float normalScale = 1.0f;      ///< normalTexture.scale
};

/// Reads materials[@p k] of @p gltf (defaults where it is absent or malformed).
GltfMaterial readGltfMaterial(const nlohmann::json& gltf, size_t k);

/// The textures of one glTF file, each decoded once. A texture that cannot be read (missing or broken image,
/// an image type other than PNG and JPEG) is left out, as other renderers do: its factor is used alone, and
/// report() names it.
class GltfTextures {
 public:
  explicit GltfTextures(const GltfFile& file) : file_(file) {}
  /// The base-colour texture of @p ref (image read through OpenImageIO, sRGB decoded; its sampler's wrap modes and
  /// filter, and its transform), or nullptr when there is none or it cannot be read (then report() names it).
  std::shared_ptr<const Texture> texture(const GltfTextureRef& ref, bool srgb = true);
  /// The image of @p ref (sRGB decoded when @p srgb), or nullptr when there is none or it cannot be read.
  const TextureImage* image(const GltfTextureRef& ref, bool srgb);
  /// The sampler's wrap modes (u, v) of @p ref; repeat by default.
  std::pair<TextureWrap, TextureWrap> wrap(const GltfTextureRef& ref) const;
  /// The sampler of @p ref's texture (samplers[textures[ref.texture].sampler]), or nullptr when it has none.
  const nlohmann::json* sampler(const GltfTextureRef& ref) const;
  /// Prints one line on stderr when textures could not be read: "F: N textures not read, their factors used
  /// alone (first: why)". @return the line, or "".
  std::string report(const std::string& file) const;

 private:
  const GltfFile& file_;
  std::map<std::pair<int64_t, bool>, std::optional<TextureImage>> images_;
  std::map<std::pair<int64_t, bool>, std::shared_ptr<const TexelImage>> texels_;  ///< by (texture, sRGB), read once (null: failed)
  std::vector<std::string> failures_;
};

/// The pbr material (MaterialType::Pbr, the glTF metallic-roughness BRDF of common/materials/bsdf.h) of base colour @p base,
/// @p metallic, @p roughness (each clamped to [0, 1]) and @p ior (≤ 0, KHR_materials_ior's "infinite" 0, becomes 10⁴).
MaterialDesc metallicRoughnessMaterial(const Color& base, float metallic, float roughness, float ior = 1.5f);

/// The names in @p gltf's extensionsUsed that the import neither reads nor may ignore without changing how
/// surfaces look (clearcoat, sheen, specular, transmission, volume, ...: every name but a list of handled ones).
std::vector<std::string> unsupportedGltfExtensions(const nlohmann::json& gltf);

/// Prints one line on stderr naming unsupportedGltfExtensions(@p gltf): "F: glTF extensions not supported,
/// ignored: A, B". @return the line, or "" when there are none.
std::string reportUnsupportedGltfExtensions(const nlohmann::json& gltf, const std::string& file);

/// The material of @p g. With KHR_materials_transmission (t = transmission × the mean R of its texture × (1 −
/// metallic) > 0), glass: a thin pane (ThinGlass; glTF's thin-walled default) of transmittance base colour × t × a
/// lossless pane's at its ior, or with KHR_materials_volume a solid dielectric tinted by base colour × t; the rest of
/// the base (1 − t of the diffuse layer) is dropped; the roughness (× its texture's mean G where that texture is folded
/// in) is the glass's (glassRoughness: rough glass, common/materials/rough_dielectric.h). Else the pbr material: its
/// metallic-roughness texture multiplies metallic (B) and roughness (G) per point when read through TEXCOORD_0, else
/// is folded in as its means; its base-colour texture likewise: the albedo texture (albedo = the base colour factor
/// × the texel per point) or its mean. Emission is g.emissive, without its texture (it depends on the mesh: emissionOnMesh).
MaterialDesc convertGltfMaterial(const GltfMaterial& g, GltfTextures& textures);

/// The emission of @p g on a mesh whose triangles cover @p uv (in TEXCOORD_<emissiveTexture.texCoord>, weighted
/// by their area in m²): g.emissive × the emissive texture's mean over those texels (meanOverTriangles). Without
/// such coordinates, or when the texture cannot be read: over the whole texture, or g.emissive alone.
Color emissionOnMesh(const GltfMaterial& g, GltfTextures& textures, const std::vector<UvTriangle>* uv);

}  // namespace firstshot
