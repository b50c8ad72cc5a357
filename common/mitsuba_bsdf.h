#pragma once
/// @file mitsuba_bsdf.h
/// Mitsuba 3 `<bsdf>` plugins mapped to the project's materials (diffuse, mirror, dielectric and the
/// metallic-roughness pbr material for the plastics and the rough conductor), with their bitmap textures. Every
/// approximation is printed once per plugin type; docs/scene-format.md, "Mitsuba 3 XML scenes", states each mapping.
#include <map>

#include "common/mitsuba_texture.h"
#include "common/mitsuba_xml.h"
#include "common/scene_desc.h"

namespace fs::mitsuba {

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

  Document& doc_;
  SceneDesc& scene_;
  TextureMapper& textures_;
  std::map<pugi::xml_node, int> done_;
  int default_ = -1;
};

}  // namespace fs::mitsuba
