#pragma once
/// @file shooting_emitters.h
/// What the shooting integrators (light tracing, bidirectional path tracing) shoot particles
/// from, and their table mode: with a first-shot table and IntegratorOptions::shootFromPatches,
/// the small lights are not shot; particles leave the kept lights and the lit patch sides
/// (EmissionSampler's table mode), so the table is the small lights' first bounce, and the small
/// lights' own part comes from the camera side (small_lights.h). Otherwise every light is shot.
#include "render/firstshot/lighting.h"
#include "render/integrators/integrator.h"
#include "render/integrators/common/small_lights.h"
#include "render/lights/light_emission.h"
#include "render/scene/render_scene.h"

namespace firstshot {

class ShootingEmitters {
 public:
  /// Chooses the mode and builds the emission sampler (and in table mode the small lights' part).
  /// @p scene and @p lighting (built for @p scene, the integrator's) must outlive the object.
  void build(const RenderScene& scene, const FirstShotLighting& lighting, const IntegratorOptions& options);

  /// Table mode: a first-shot table is loaded and IntegratorOptions::shootFromPatches is set.
  bool tableMode() const { return table_; }
  /// The emitters particles leave: every light, or in table mode the kept lights and lit patch sides.
  const EmissionSampler& emission() const { return emission_; }
  /// Table mode: the small lights' own part of a camera subpath.
  const SmallLightsExact& smallLights() const { return small_; }

 private:
  bool table_ = false;
  EmissionSampler emission_;
  SmallLightsExact small_;
};

}  // namespace firstshot
