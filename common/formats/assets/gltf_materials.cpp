// glTF metallic-roughness materials from the JSON, textures folded into factors (common/formats/assets/gltf_materials.h).
#include "common/formats/assets/gltf_materials.h"

#include <algorithm>
#include <cstdio>
#include <set>

#include "common/materials/thin_glass.h"
#include "common/util/error.h"

namespace firstshot {
namespace {

using Json = nlohmann::json;

// The member readers of gltf_file.cpp have this shape too, for the types that file reads.
float number(const Json& j, const char* key, float fallback) {
  const Json* v = jsonMember(j, key);
  return v && v->is_number() ? v->get<float>() : fallback;
}

/// The first three numbers of the array @p j[key], or @p fallback.
Color color(const Json& j, const char* key, const Color& fallback) {
  const Json* v = jsonMember(j, key);
  if (!v || !v->is_array() || v->size() < 3) return fallback;
  Color c;
  for (int i = 0; i < 3; ++i) {
    if (!(*v)[i].is_number()) return fallback;
    c[i] = (*v)[i].get<float>();
  }
  return c;
}

GltfTextureRef textureRef(const Json& j, const char* key) {
  GltfTextureRef ref;
  const Json* info = jsonMember(j, key);
  const Json* index = info ? jsonMember(*info, "index") : nullptr;
  if (!index || !index->is_number_unsigned() || index->get<uint64_t>() > uint64_t(INT64_MAX)) return ref;
  ref.texture = index->get<int64_t>();
  const Json* set = jsonMember(*info, "texCoord");
  if (set && set->is_number_unsigned() && set->get<uint64_t>() < 8) ref.texCoord = set->get<unsigned>();
  const Json* extensions = jsonMember(*info, "extensions");
  if (const Json* t = extensions ? jsonMember(*extensions, "KHR_texture_transform") : nullptr) {
    const auto pair = [&](const char* name, Vec2& out) {
      const Json* v = jsonMember(*t, name);
      if (v && v->is_array() && v->size() == 2 && (*v)[0].is_number() && (*v)[1].is_number())
        out = Vec2((*v)[0].get<float>(), (*v)[1].get<float>());
    };
    pair("offset", ref.transform.offset);
    pair("scale", ref.transform.scale);
    ref.transform.rotation = number(*t, "rotation", 0.0f);
    const Json* over = jsonMember(*t, "texCoord");
    if (over && over->is_number_unsigned() && over->get<uint64_t>() < 8) ref.texCoord = over->get<unsigned>();
  }
  return ref;
}

/// textures[ref.texture] of @p gltf, or nullptr.
const Json* textureJson(const Json& gltf, const GltfTextureRef& ref) {
  return ref.texture < 0 ? nullptr : jsonArrayElement(gltf, "textures", uint64_t(ref.texture));
}

/// The index in images[] of the source of texture @p ref (named @p where in errors); InputError when the texture does
/// not exist or, with the message @p where + @p noSource, has no source.
size_t textureSource(const Json& gltf, const GltfTextureRef& ref, const std::string& where, const char* noSource) {
  const Json* t = textureJson(gltf, ref);
  const Json* source = t ? jsonMember(*t, "source") : nullptr;
  if (!t) throw InputError("", "", where + " does not exist");
  if (!source || !source->is_number_unsigned()) throw InputError("", "", where + noSource);
  return source->get<size_t>();
}

TextureWrap wrapMode(const Json* sampler, const char* key) {
  const Json* v = sampler ? jsonMember(*sampler, key) : nullptr;
  const int64_t mode = v && v->is_number_integer() ? v->get<int64_t>() : 10497;
  return mode == 33071 ? TextureWrap::ClampToEdge : mode == 33648 ? TextureWrap::MirroredRepeat : TextureWrap::Repeat;
}

/// The lookup filter of a sampler (glTF 2.0, 5.26): magFilter, NEAREST (9728) or LINEAR (9729), decides, being
/// what shows where a texel covers a pixel or more; without it the minFilter's filter within a level, NEAREST or
/// NEAREST_MIPMAP_* (9728, 9984, 9986) against LINEAR or LINEAR_MIPMAP_* (9729, 9985, 9987), the choice between
/// MIP levels having no meaning without MIP maps (common/materials/texture.h). Neither: linear, the usual default.
TextureFilter filterMode(const Json* sampler) {
  for (const char* key : {"magFilter", "minFilter"}) {
    const Json* v = sampler ? jsonMember(*sampler, key) : nullptr;
    if (!v || !v->is_number_integer()) continue;
    const int64_t mode = v->get<int64_t>();
    if (mode == 9728 || mode == 9984 || mode == 9986) return TextureFilter::Nearest;
    if (mode == 9729 || mode == 9985 || mode == 9987) return TextureFilter::Linear;
  }
  return TextureFilter::Linear;
}

Color rgb(const std::array<float, 4>& v) { return {v[0], v[1], v[2]}; }

}  // namespace

namespace {

/// Material @p m's alpha: alphaMode, alphaCutoff and baseColorFactor's fourth number, into @p g.
void readGltfAlpha(const Json& m, GltfMaterial& g) {
  const Json* mode = jsonMember(m, "alphaMode");
  if (mode && mode->is_string())
    g.alphaMode = *mode == "MASK" ? AlphaMode::Mask : *mode == "BLEND" ? AlphaMode::Blend : AlphaMode::Opaque;
  g.alphaCutoff = std::clamp(number(m, "alphaCutoff", g.alphaCutoff), 0.0f, 1.0f);
  const Json* pbr = jsonMember(m, "pbrMetallicRoughness");
  const Json* factor = pbr ? jsonMember(*pbr, "baseColorFactor") : nullptr;
  if (factor && factor->is_array() && factor->size() >= 4 && (*factor)[3].is_number())
    g.alpha = std::clamp((*factor)[3].get<float>(), 0.0f, 1.0f);
}

/// @p m's alpha from @p g: its mode, cut-off and factor, and the base-colour texture's A channel when it has one.
/// An emitting material stays opaque (an emitter cannot be a cut-out).
void convertGltfAlpha(const GltfMaterial& g, MaterialDesc& m) {
  if (g.alphaMode == AlphaMode::Opaque || m.isEmissive()) return;
  m.alphaMode = g.alphaMode;
  m.alphaCutoff = g.alphaCutoff;
  m.alpha = g.alpha;
  if (m.albedoTexture && !m.albedoTexture->image->alpha.empty()) m.alphaTexture = m.albedoTexture;
}

}  // namespace

GltfMaterial readGltfMaterial(const Json& gltf, size_t k) {
  GltfMaterial g;
  const Json* material = jsonArrayElement(gltf, "materials", k);
  if (!material) return g;
  const Json& m = *material;
  if (const Json* pbr = jsonMember(m, "pbrMetallicRoughness")) {
    g.baseColor = color(*pbr, "baseColorFactor", g.baseColor);
    g.metallic = number(*pbr, "metallicFactor", g.metallic);
    g.roughness = number(*pbr, "roughnessFactor", g.roughness);
    g.baseColorTexture = textureRef(*pbr, "baseColorTexture");
    g.metallicRoughnessTexture = textureRef(*pbr, "metallicRoughnessTexture");
  }
  g.emissive = color(m, "emissiveFactor", g.emissive);
  g.emissiveTexture = textureRef(m, "emissiveTexture");
  g.normalTexture = textureRef(m, "normalTexture");
  if (const Json* normal = jsonMember(m, "normalTexture")) g.normalScale = number(*normal, "scale", g.normalScale);
  const Json* extensions = jsonMember(m, "extensions");
  const Json* strength = extensions ? jsonMember(*extensions, "KHR_materials_emissive_strength") : nullptr;
  if (strength) g.emissive *= number(*strength, "emissiveStrength", 1.0f);
  const Json* ior = extensions ? jsonMember(*extensions, "KHR_materials_ior") : nullptr;
  if (ior) g.ior = number(*ior, "ior", g.ior);
  readGltfAlpha(m, g);
  if (const Json* t = extensions ? jsonMember(*extensions, "KHR_materials_transmission") : nullptr) {
    g.transmission = std::clamp(number(*t, "transmissionFactor", 0.0f), 0.0f, 1.0f);
    g.transmissionTexture = textureRef(*t, "transmissionTexture");
  }
  if (const Json* v = extensions ? jsonMember(*extensions, "KHR_materials_volume") : nullptr)
    g.volume = number(*v, "thicknessFactor", 0.0f) > 0.0f;
  return g;
}

const TextureImage* GltfTextures::image(const GltfTextureRef& ref, bool srgb) {
  if (ref.texture < 0) return nullptr;
  auto [it, inserted] = images_.try_emplace({ref.texture, srgb});
  if (!inserted) return it->second ? &*it->second : nullptr;
  const std::string where = "textures[" + std::to_string(ref.texture) + "]";
  try {
    const size_t source = textureSource(file_.json(), ref, where, " has no PNG or JPEG source");
    it->second = decodeTextureImage(file_.imageBytes(source), srgb);
  } catch (const InputError& e) {
    failures_.push_back(where + ": " + e.what());
  }
  return it->second ? &*it->second : nullptr;
}

std::shared_ptr<const Texture> GltfTextures::texture(const GltfTextureRef& ref, bool srgb) {
  if (ref.texture < 0) return nullptr;
  auto [it, inserted] = texels_.try_emplace(std::make_pair(ref.texture, srgb));
  if (inserted) {
    const std::string where = "textures[" + std::to_string(ref.texture) + "]";
    try {
      const size_t source = textureSource(file_.json(), ref, where, " has no image source");
      const std::string name = file_.path().string() + " images[" + std::to_string(source) + "]";
      it->second = std::make_shared<const TexelImage>(decodeTexelImage(file_.imageBytes(source), name, srgb));
    } catch (const InputError& e) {
      failures_.push_back(where + ": " + e.what());
    }
  }
  if (!it->second) return nullptr;
  auto texture = std::make_shared<Texture>();
  texture->image = it->second;
  std::tie(texture->wrapU, texture->wrapV) = wrap(ref);
  texture->filter = filterMode(sampler(ref));
  texture->transform = ref.transform;
  return texture;
}

const nlohmann::json* GltfTextures::sampler(const GltfTextureRef& ref) const {
  const Json* t = textureJson(file_.json(), ref);
  const Json* index = t ? jsonMember(*t, "sampler") : nullptr;
  return index && index->is_number_unsigned() ? jsonArrayElement(file_.json(), "samplers", index->get<uint64_t>()) : nullptr;
}

std::pair<TextureWrap, TextureWrap> GltfTextures::wrap(const GltfTextureRef& ref) const {
  const Json* s = sampler(ref);
  return {wrapMode(s, "wrapS"), wrapMode(s, "wrapT")};
}

std::string GltfTextures::report(const std::string& file) const {
  if (failures_.empty()) return "";
  const std::string line = file + ": " + std::to_string(failures_.size()) +
                           (failures_.size() == 1 ? " texture" : " textures") +
                           " not read, their factors used alone (first: " + failures_.front() + ")";
  std::fprintf(stderr, "%s\n", line.c_str());
  return line;
}

MaterialDesc metallicRoughnessMaterial(const Color& base, float metallic, float roughness, float ior) {
  MaterialDesc m;
  m.type = MaterialType::Pbr;
  m.albedo = glm::clamp(base, Color(0.0f), Color(1.0f));
  m.metallic = std::clamp(metallic, 0.0f, 1.0f);
  m.roughness = std::clamp(roughness, 0.0f, 1.0f);
  // KHR_materials_ior: 0 means f0 = 1 (a full mirror coat); the model needs an ior > 0, and 10⁴ is f0 ≈ 1.
  m.ior = ior > 0.0f ? ior : 1e4f;
  return m;
}

std::vector<std::string> unsupportedGltfExtensions(const Json& gltf) {
  // Read here or by assimp, or with no effect on what a surface looks like (KHR_texture_transform: not on a texture's
  // mean; KHR_materials_variants: the default material is the file's own).
  static const std::set<std::string> handled = {
      "KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_lights_punctual", "KHR_mesh_quantization",
      "KHR_texture_transform", "KHR_materials_variants", "KHR_xmp_json_ld", "KHR_materials_transmission",
      "KHR_materials_volume"};
  std::vector<std::string> names;
  const Json* used = jsonMember(gltf, "extensionsUsed");
  if (!used || !used->is_array()) return names;
  for (const Json& e : *used)
    if (e.is_string() && !handled.count(e.get<std::string>())) names.push_back(e.get<std::string>());
  return names;
}

std::string reportUnsupportedGltfExtensions(const Json& gltf, const std::string& file) {
  const std::vector<std::string> names = unsupportedGltfExtensions(gltf);
  if (names.empty()) return "";
  std::string line = file + ": glTF extension" + (names.size() == 1 ? "" : "s") + " not supported, ignored:";
  for (size_t i = 0; i < names.size(); ++i) line += (i ? ", " : " ") + names[i];
  std::fprintf(stderr, "%s\n", line.c_str());
  return line;
}

MaterialDesc convertGltfMaterial(const GltfMaterial& g, GltfTextures& textures) {
  Color base = g.baseColor;
  float metallic = g.metallic, roughness = g.roughness;
  std::shared_ptr<const Texture> albedoTexture;
  if (g.baseColorTexture.texCoord == 0) albedoTexture = textures.texture(g.baseColorTexture);
  if (albedoTexture) base *= albedoTexture->image->mean;
  else if (const TextureImage* t = textures.image(g.baseColorTexture, true)) base *= rgb(t->mean());
  std::shared_ptr<const Texture> mrTexture;
  if (g.metallicRoughnessTexture.texCoord == 0) mrTexture = textures.texture(g.metallicRoughnessTexture, false);
  if (!mrTexture)
    if (const TextureImage* t = textures.image(g.metallicRoughnessTexture, false)) {
      const std::array<float, 4> mean = t->mean();
      metallic *= mean[2];
      roughness *= mean[1];
    }
  MaterialDesc m = metallicRoughnessMaterial(base, metallic, roughness, g.ior);
  if (albedoTexture) {  // the texture multiplies the base colour factor per point
    m.albedo = metallicRoughnessMaterial(g.baseColor, metallic, roughness, g.ior).albedo;
    m.albedoTexture = std::move(albedoTexture);
  }
  m.metallicRoughnessTexture = std::move(mrTexture);  // it multiplies the factors per point
  m.emission = g.emissive;
  // The normal map, read linear, when it uses the coordinates the shapes keep (TEXCOORD_0); otherwise
  // the surface stays unperturbed (a normal map has no mean to fold in).
  if (g.normalTexture.texCoord == 0)
    if ((m.normalTexture = textures.texture(g.normalTexture, false))) m.normalScale = g.normalScale;
  convertGltfAlpha(g, m);
  float t = g.transmission * (1.0f - std::clamp(metallic, 0.0f, 1.0f));
  if (t > 0.0f)
    if (const TextureImage* tt = textures.image(g.transmissionTexture, false)) t *= tt->mean()[0];
  if (t > 0.0f) {  // KHR_materials_transmission: glass (see the header)
    MaterialDesc glass;
    glass.emission = g.emissive;
    glass.ior = g.ior >= 1.0f ? g.ior : 1.5f;
    const Color tint = glm::clamp(base * t, Color(0.0f), Color(1.0f));
    glass.type = g.volume ? MaterialType::Dielectric : MaterialType::ThinGlass;
    glass.transmittance = g.volume ? tint : tint * ThinGlassBSDF::maxTransmittance(glass.ior);
    glass.glassRoughness = std::clamp(roughness, 0.0f, 1.0f);  // rough glass (× the texture's mean where it was folded in)
    return glass;
  }
  return m;
}

Color emissionOnMesh(const GltfMaterial& g, GltfTextures& textures, const std::vector<UvTriangle>* uv) {
  if (!(maxComponent(g.emissive) > 0.0f)) return g.emissive;
  const TextureImage* t = textures.image(g.emissiveTexture, true);
  if (!t) return g.emissive;
  if (!uv) return g.emissive * rgb(t->mean());
  const auto [wrapU, wrapV] = textures.wrap(g.emissiveTexture);
  return g.emissive * rgb(meanOverTriangles(*t, *uv, wrapU, wrapV));
}

}  // namespace firstshot
