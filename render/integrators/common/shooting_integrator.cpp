// The shooting integrators' common preprocessing: the scene's first-shot lighting and the emitters.
#include "render/integrators/common/shooting_integrator.h"

#include "render/integrators/common/luminaire_split.h"

namespace firstshot {

void ShootingIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  lighting_.build(scene);
  shooting_.build(scene, lighting_, options_);  // in table mode: the kept lights and the lit patch sides
  luminaires_ = options_.luminaires && !scene.luminaires().empty();
  withExits_ = luminaires_ ? emittersWithExits(scene, shooting_.emission(), options_.maxDepth,
                                               options_.splitEveryLuminaire)
                           : EmissionSampler();
}

}  // namespace firstshot
