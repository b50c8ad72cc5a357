#pragma once
/// @file mitsuba_shapes.h
/// Mitsuba `<shape>` plugins turned into SceneDesc shapes: meshes from files (`obj`, `ply`, `serialized`), the
/// built-in shapes tessellated (`rectangle`, `cube`, `sphere`, `disk`, `cylinder`), and `shapegroup`s whose
/// `instance`s become transformed copies of the group's shapes. docs/scene-format.md, "Mitsuba 3 XML scenes",
/// states each mapping and what differs from Mitsuba.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/formats/mitsuba/mitsuba_bsdf.h"
#include "common/formats/mitsuba/mitsuba_xml.h"
#include "common/scene/scene_desc.h"

namespace firstshot::mitsuba {

/// Adds the shapes of a scene's `<shape>` elements to a SceneDesc, with their materials.
class ShapeMapper {
 public:
  /// Turns a file name given in the scene into the path to open (the scene's folder, then its `<path>` folders).
  using Resolver = std::function<std::filesystem::path(const std::string&)>;

  ShapeMapper(Document& doc, SceneDesc& scene, BsdfMapper& bsdfs, Resolver resolve)
      : doc_(doc), scene_(scene), bsdfs_(bsdfs), resolve_(std::move(resolve)) {}

  /// Adds what the top-level `<shape>` @p node puts in the scene: one shape (its bsdf's material; an area emitter
  /// inside makes it emissive), nothing for a `shapegroup` (its shapes are made here, for its instances), and for an
  /// `instance` a copy of each shape of its group transformed by the instance's to_world.
  /// @throws InputError naming the element for unsupported types and bad values.
  void add(pugi::xml_node node);

 private:
  /// One shape of @p node with its material; @p inGroup: inside a shapegroup, where emitters and nested groups or
  /// instances are refused as Mitsuba refuses them.
  ShapeDesc make(pugi::xml_node node, bool inGroup);
  /// The polygons of @p p's type, untransformed.
  void geometry(Plugin& p, ShapeDesc& s);
  /// The shapes of the shapegroup @p node, made on first use.
  const std::vector<ShapeDesc>& group(pugi::xml_node node);
  void instance(pugi::xml_node node);

  Document& doc_;
  SceneDesc& scene_;
  BsdfMapper& bsdfs_;
  Resolver resolve_;
  std::map<pugi::xml_node, std::vector<ShapeDesc>> groups_;  ///< each shapegroup's shapes, as its elements place them
};

/// Mitsuba's `cylinder` as the mesh of @p s (empty before): the open tube of @p radius (m) from @p p0 to @p p1 (its
/// centre line, m), without end caps, normals outward, as kCylinderSegments planar quads around the axis whose
/// radius is enlarged so that their area is the cylinder's, 2π·radius·|p1 − p0|. Each corner has the cylinder's own
/// normal (smooth shading) and Mitsuba's texture coordinates: u = φ/2π around the axis, from Mitsuba's seam, v = 0
/// at p0 to 1 at p1.
void makeCylinder(ShapeDesc& s, const Vec3d& p0, const Vec3d& p1, double radius);

/// Quads around a tessellated cylinder: facets 5.625° wide, their corners 0.04% outside the true radius and their
/// middles 0.08% inside it, the area exact.
inline constexpr int kCylinderSegments = 64;

}  // namespace firstshot::mitsuba
