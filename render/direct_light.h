#pragma once
/// @file direct_light.h
/// Direct lighting shared by the integrators: next-event estimation (NEE) to the scene's lights
/// and the first-shot term of a first-shot table.
///
/// First-shot term on patch j (see common/firstshot.h): Σ_i emission_i · r_ij · f_r(ω'_i, x, ω),
/// with ω'_i the direction from x to light sample i (against the travel direction for
/// directional lights). The BSDF's side test makes a sample on the other side of the patch than
/// the viewer contribute nothing.
#include <cstdint>
#include <vector>

#include "common/bsdf.h"
#include "common/math.h"
#include "common/rng.h"
#include "render/ray.h"
#include "render/render_scene.h"

namespace fs {

/// Power heuristic (β = 2) weight of a technique with density @p a against one with density @p b.
inline float powerHeuristic(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

/// A shadow ray from the hit towards a light @p distance away in direction @p wi. The far end
/// stops short of the light, which may be emitter geometry itself.
Ray shadowRay(const Hit& hit, const Vec3& wi, float distance);

/// The first-shot term of a scene's table. On a Lambertian patch it is ρ/π times one of two
/// irradiances (the factors summed per side of the patch's plane), precomputed by build().
class FirstShotLighting {
 public:
  /// Sums each patch's factors per side of its plane; no-op without a table. @p scene must outlive this.
  void build(const RenderScene& scene);
  /// The first-shot radiance reflected at a hit on patch hit.patch towards the local @p woLocal.
  /// Requires a table and a hit on a patch.
  Color eval(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const;

 private:
  const RenderScene* scene_ = nullptr;
  /// Per patch j: first-shot irradiance from samples in front of (2j) and behind (2j+1) its plane.
  std::vector<Color> sideIrradiance_;
};

/// Which lights estimateDirect() samples, and how it weights them.
struct DirectLightOptions {
  bool skipReplaced = false;  ///< leave out the small lights a first-shot table replaces
  /// If set: only lights l with (*include)[l] != 0 (indexed like LightSet::lights()).
  const std::vector<uint8_t>* include = nullptr;
  /// Area lights: power-heuristic weight against BSDF sampling (which must then count the
  /// emission it meets, with the complementary weight); false: weight 1 (BSDF sampling must not count them).
  bool mis = true;
  /// Integrate only f − ρd/π, the BSDF without its Lambertian part (the part an irradiance cache leaves out).
  bool nonDiffuseOnly = false;
};

/// One NEE sample per selected light: Σ_l f·|cos θ_i|·L_l/pdf_l·weight, unoccluded samples only.
/// Draws one 2D number per light of the scene, selected or not, so later dimensions do not shift.
/// @p rays is incremented by the shadow rays traced.
Color estimateDirect(const RenderScene& scene, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                     const DirectLightOptions& options, Sampler& sampler, uint64_t& rays);

}  // namespace fs
