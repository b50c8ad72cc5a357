// The shooting integrators' emitters: every light, or in table mode the kept lights and lit patches.
#include "render/integrators/common/shooting_emitters.h"

namespace firstshot {

void ShootingEmitters::build(const RenderScene& scene, const FirstShotLighting& lighting,
                             const IntegratorOptions& options) {
  table_ = options.shootFromPatches && scene.firstShot() != nullptr;
  if (!table_) {
    emission_ = EmissionSampler(scene.lights(), scene.desc());
    return;
  }
  emission_ = EmissionSampler(scene, lighting);
  small_.build(scene, lighting, options);
}

}  // namespace firstshot
