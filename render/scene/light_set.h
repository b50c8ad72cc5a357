#pragma once
/// @file light_set.h
/// The renderer's lights: next-event estimation samples for point, spot, directional and area
/// lights, and the emission of area-light geometry met by a path. Emission profiles come from
/// common/lights/emission_profile.h so that the preprocessor and the renderer agree.
#include <cstdint>
#include <memory>
#include <vector>

#include "common/lights/emission_profile.h"
#include "common/sampling/distribution_1d.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"
#include "render/scene/embree_scene.h"
#include "render/scene/environment_map.h"

namespace firstshot {

/// One light as the renderer sees it.
struct RenderLight {
  LightType type = LightType::Point;
  uint32_t sceneIndex = 0;  ///< index into SceneDesc::lights
  bool replaced = false;    ///< a small light whose first reflection comes from the first-shot table
  LightDesc desc;           ///< the scene's definition (spot profile, names for messages)
  Vec3 position{0.0f};      ///< point, spot
  Vec3 direction{0, -1, 0}; ///< spot: axis; directional: direction the light travels in
  Color intensity{0.0f};    ///< point, spot: Φ/∫profile dω, the intensity where the profile is 1 (W/sr)
  EmissionProfile profile;  ///< point, spot: relative intensity per world direction (common/lights/emission_profile.h)
  Color irradiance{0.0f};   ///< directional: E⊥ (W/m²)
  // Area lights.
  uint32_t emitter = 0;     ///< index of its EmitterMesh (Hit::emitter)
  Color radiance{0.0f};     ///< Le, emitted from the front side only (W/(m² sr))
  Distribution1Df triangles;  ///< the emitter's triangles by area (their values: the areas, m²)
  double area = 0;          ///< total area, m²
  // Emission per point (common/materials/emission_texture.h): an emitter whose material has an emission texture.
  /// Its material when it emits per point (LightSet::radianceAt looks the texel up); null: `radiance` everywhere.
  std::shared_ptr<const MaterialDesc> textured;
  std::vector<Vec2> triangleUv;         ///< textured: the texture coordinates of each triangle's 3 corners
  std::vector<Color> triangleRadiance;  ///< textured: each triangle's mean radiance (the light tree's power)

  bool isDelta() const { return type != LightType::Area; }
};

/// A light sample seen from a shading point x.
struct LightRecord {
  Vec3 wi{0.0f};         ///< unit direction from x towards the light
  float distance = 0;    ///< from x to the sampled point (infinity for a directional light)
  Color value{0.0f};     ///< incident radiance over the sampling density: the contribution is f·|cos θ_i|·value
  float pdf = 0;         ///< solid-angle density of wi (area lights); 0 for delta lights
};

/// All lights of a scene, with the triangle meshes of the area lights.
class LightSet {
 public:
  LightSet() = default;
  /// @param replaced indices into scene.lights of the small lights handled by a first-shot table
  LightSet(const SceneDesc& scene, const std::vector<uint32_t>& replaced);

  const std::vector<RenderLight>& lights() const { return lights_; }
  /// The area light's triangles, indexed like Hit::emitter.
  const std::vector<EmitterMesh>& emitterMeshes() const { return meshes_; }
  /// The area light that owns emitter mesh @p emitter.
  const RenderLight& emitterLight(uint32_t emitter) const { return lights_[emitterLight_[emitter]]; }
  /// Number of lights not replaced by first-shot.
  size_t unreplacedCount() const;
  /// The scene's infinite light (a sky or an environment map, render/scene/sky_light.h), or null: radiance from
  /// infinitely far away, a large light never replaced by first-shot (not one of lights()).
  const EnvironmentMap* environment() const { return environment_.get(); }
  /// Radiance of the infinite light along @p dir (unit) where no light sampling could have found it (camera rays,
  /// after a mirror or glass): a sky's model itself (smooth at any map resolution; no MIS weight pairs it with the
  /// map), an environment map's texel; 0 without either.
  Color background(const Vec3& dir) const;

  /// Samples light @p l from the shading point @p x with @p u ∈ [0,1)².
  /// @return false when the light sends nothing towards x (outside a spot cone, behind an area
  ///         light, degenerate geometry); out is then unspecified.
  bool sample(const RenderLight& l, const Vec3& x, const Vec2& u, LightRecord& out) const;

  /// A point of area light @p l, uniform by area, from @p u ∈ [0,1)²: position @p y (m) and the
  /// front side's unit normal @p n, and unless null the radiance @p le leaving it (radianceAt).
  /// @return false for a light without area.
  bool samplePoint(const RenderLight& l, const Vec2& u, Vec3& y, Vec3& n, Color* le = nullptr) const;

  /// Radiance leaving the emitter of @p hit (a hit on an area light) towards @p wo (unit, pointing away from the
  /// emitter): Le at the hit's point (radianceAt) on the front side, 0 behind.
  Color emitted(const Hit& hit, const Vec3& wo) const;

  /// Radiance Le (front side) of area light @p l at the point of barycentric coordinates @p bary (of the second
  /// and third vertex) of its triangle @p t: l.radiance, or for a textured emitter emissionFactor × the texel there.
  Color radianceAt(const RenderLight& l, uint32_t t, const Vec2& bary) const;

  /// Solid-angle density with which sample() picks the point @p y (normal @p ng) of area light
  /// @p l, seen from @p x. Zero behind the light.
  float pdf(const RenderLight& l, const Vec3& x, const Vec3& y, const Vec3& ng) const;

 private:
  std::vector<RenderLight> lights_;
  std::vector<EmitterMesh> meshes_;
  std::vector<uint32_t> emitterLight_;  ///< emitter mesh -> index into lights_
  std::shared_ptr<const EnvironmentMap> environment_;
  std::shared_ptr<const SkyDesc> sky_;  ///< the scene's sky, for background()
};

}  // namespace firstshot
