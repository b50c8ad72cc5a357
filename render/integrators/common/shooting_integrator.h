#pragma once
/// @file shooting_integrator.h
/// What the shooting integrators (light tracing, render/integrators/light/; bidirectional path
/// tracing, render/integrators/bdpt/) share as integrators: their settings, the scene, its
/// first-shot lighting and the emitters their particles leave (ShootingEmitters, with the table
/// mode), all made once by preprocess(). Each adds its own particles, splats and camera side.
#include <memory>
#include <string>

#include "render/firstshot/lighting.h"
#include "render/integrators/common/emitter_importance.h"
#include "render/integrators/common/shooting_emitters.h"
#include "render/integrators/integrator.h"

namespace firstshot {

class ShootingIntegrator : public SplattingIntegrator {
 public:
  explicit ShootingIntegrator(const IntegratorOptions& options) : options_(options) {}
  /// The emitters particles leave: every light, or in table mode the kept lights and lit patch sides.
  const EmissionSampler& emission() const { return shooting_.emission(); }
  /// What the particles leave: emission(), and with the luminaires their exit patches too (emittersWithExits,
  /// luminaire_split.h: each luminaire split where that pays).
  /// Once chooseEmitters() has run, their copy with the camera's choice.
  const EmissionSampler& particleEmitters() const {
    return chosen_ ? chosenEmitters_ : luminaires_ ? withExits_ : shooting_.emission();
  }
  /// How chooseEmitters() chose the particles' emitters (no groups: by power, IntegratorOptions::cameraEmitterChoice).
  const EmitterImportance& emitterImportance() const { return *importance_; }
  /// Whether the particles use the luminaires' exit distributions (preprocess()).
  bool usesLuminaires() const { return luminaires_; }
  /// Keeps @p scene (which must outlive the integrator's use), builds its first-shot lighting and
  /// the emitters. An integrator that overrides it calls it first.
  void preprocess(const RenderScene& scene) override;

 protected:
  IntegratorOptions options_;
  const RenderScene* scene_ = nullptr;
  FirstShotLighting lighting_;  ///< the table's lighting (table mode: the lit patches' emission), built once
  ShootingEmitters shooting_;   ///< the emitters; in table mode also the small lights' own part
  /// IntegratorOptions::luminaires and the scene has luminaires: the particles leave withExits_.
  bool luminaires_ = false;
  EmissionSampler withExits_;  ///< emission() and the luminaires' exit patches

  /// With IntegratorOptions::cameraEmitterChoice, measures the emitters particleEmitters() gives (measureEmitterImportance:
  /// particles traced by @p walk, scored by @p moment, the integrator's camera splats) and from then on particleEmitters()
  /// is their copy chosen by the camera. Measured once per scene, emitters and @p integrator (the scene's memo: the
  /// pilot's candidates and the render share it). Called by an integrator's preprocess() once its splats' rules are set.
  void chooseEmitters(const std::string& integrator, const LightPathOptions& walk, const PathSplatMoment& moment);

 private:
  bool chosen_ = false;                  ///< chooseEmitters() reweighted chosenEmitters_
  EmissionSampler chosenEmitters_;       ///< particleEmitters() as chooseEmitters() found them, reweighted
  std::shared_ptr<const EmitterImportance> importance_ = std::make_shared<const EmitterImportance>();
};

}  // namespace firstshot
