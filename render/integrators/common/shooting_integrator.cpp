// The shooting integrators' common preprocessing: the scene's first-shot lighting and the emitters.
#include "render/integrators/common/shooting_integrator.h"

#include <fmt/core.h>

#include "render/integrators/common/luminaire_split.h"

namespace firstshot {

void ShootingIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  chosen_ = false;
  importance_ = std::make_shared<const EmitterImportance>();
  lighting_.build(scene);
  shooting_.build(scene, lighting_, options_);  // in table mode: the kept lights and the lit patch sides
  luminaires_ = options_.luminaires && !scene.luminaires().empty();
  withExits_ = luminaires_ ? emittersWithExits(scene, shooting_.emission(), options_.maxDepth,
                                               options_.splitEveryLuminaire)
                           : EmissionSampler();
}

void ShootingIntegrator::chooseEmitters(const std::string& integrator, const LightPathOptions& walk,
                                        const PathSplatMoment& moment) {
  if (!options_.cameraEmitterChoice) return;
  const EmissionSampler& e = particleEmitters();
  const std::string key = fmt::format("EmitterImportance/{}/{}/{}/{}/{}/{:a}", integrator, options_.maxDepth,
                                      e.lightCount(), e.patchSideCount(), e.exits().count(), e.totalPower());
  importance_ = scene_->memo().find<EmitterImportance>(key);
  if (!importance_) {
    uint64_t rays = 0;
    importance_ = std::make_shared<const EmitterImportance>(
        measureEmitterImportance(*scene_, e, walk, luminaires_, moment, rays));
    scene_->memo().keep(key, importance_);
  }
  if (importance_->factor.empty()) return;
  chosenEmitters_ = e;
  chosenEmitters_.reweight(importance_->factor);
  chosen_ = true;
}

}  // namespace firstshot
