#pragma once
/// @file mitsuba_bsdf.h
/// Mitsuba 3 (and 0.6) `<bsdf>` plugins mapped to the project's materials (diffuse, glossy, mirror, dielectric and
/// the metallic-roughness pbr material for the plastics, coatings and the rough conductor), with their bitmap
/// textures; blendbsdf and mask in common/formats/mitsuba/mitsuba_bsdf_mix.cpp. Every approximation is printed once per plugin
/// type; docs/scene-format.md, "Mitsuba 3 XML scenes", states each mapping.
#include <map>

#include "common/formats/mitsuba/mitsuba_texture.h"
#include "common/formats/mitsuba/mitsuba_xml.h"
#include "common/scene/scene_desc.h"

namespace firstshot::mitsuba {

/// Fits a glossy material @p m to its bound albedo + specular ≤ 1 (per channel, of the factor): a textured diffuse part
/// has its factor baked into the texels (clamped to 1), leaving the factor 1 − specular; an untextured one keeps its
/// albedo and the lobe is lowered to 1 − albedo. Nothing changes within the bound.
void leaveRoomForLobe(MaterialDesc& m);

/// Turns `<bsdf>` elements into SceneDesc materials, one per element however often it is referenced.
class BsdfMapper {
 public:
  BsdfMapper(Document& doc, SceneDesc& scene, TextureMapper& textures) : doc_(doc), scene_(scene), textures_(textures) {}
  /// Index in SceneDesc::materials of the `<bsdf>` @p node (mapped on first use; named by its id, or
  /// by its element path). @throws InputError for unsupported plugins or values.
  int material(pugi::xml_node node);
  /// Mitsuba's material for a shape without a bsdf: diffuse, reflectance 0.5.
  int defaultMaterial();

 private:
  /// The material of @p node; @p wrapped: inside a twosided (no one-sided note).
  MaterialDesc map(pugi::xml_node node, bool wrapped);
  /// Mitsuba 0.6's phong and ward as the glossy material.
  MaterialDesc glossy(Plugin& p);
  /// Mitsuba 0.6's coating and roughcoating over their nested bsdf.
  MaterialDesc coated(Plugin& p, bool wrapped);
  /// blendbsdf: its two nested bsdfs mixed by weight (common/formats/mitsuba/mitsuba_bsdf_mix.cpp).
  MaterialDesc blended(Plugin& p, bool wrapped);
  /// mask: its nested bsdf as a stochastic cut-out of alpha = opacity (common/formats/mitsuba/mitsuba_bsdf_mix.cpp).
  MaterialDesc masked(Plugin& p, bool wrapped);
  /// The single nested bsdf of a wrapping plugin @p p. @throws InputError unless there is exactly one.
  pugi::xml_node onlyNested(Plugin& p);

  Document& doc_;
  SceneDesc& scene_;
  TextureMapper& textures_;
  std::map<pugi::xml_node, int> done_;
  int default_ = -1;
};

}  // namespace firstshot::mitsuba
