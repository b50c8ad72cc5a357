// A light-subpath vertex joined to the pinhole camera.
#include "render/integrators/common/camera_splat.h"

#include <cmath>

#include "render/lights/next_event.h"

namespace firstshot {

bool connectToCamera(const RenderScene& scene, const LightVertex& v, const Camera& camera, uint32_t& pixel, Color& L,
                     uint64_t& rays, bool throughPanes) {
  if (v.delta) return false;
  CameraConnection c;
  if (!camera.connect(v.hit.p, c)) return false;
  float cosX = glm::dot(v.hit.ng, c.wi);
  if (v.material == kNoId) {  // vertex 0 on an area light: Le towards the camera, front side only
    if (!(cosX > 0.0f)) return false;
    L = v.beta * (cosX * c.importance);
  } else {
    const Frame frame = scene.shadingFrame(v.hit);
    // f(light side → camera): the radiance BSDF with wi towards the light (it differs from the adjoint by
    // η² through rough glass; Importance mode means wo is the light side, as in sample()).
    const BSDFQuery q(frame.toLocal(v.wi), frame.toLocal(c.wi), TransportMode::Radiance);
    const BSDF bsdf = scene.bsdfAt(v.hit);
    const Color f = bsdf.eval(q);
    if (!(maxComponent(f) > 0.0f)) return false;
    L = v.beta * f * (std::abs(cosX) * c.importance);
    // Shading normal: f·|ω_cam·n_s| times the adjoint factor is f·|ω_cam·n_g|·|ω_prev·n_s|/|ω_prev·n_g|.
    if (bsdf.shaded()) L *= adjointCorrection(v.wi, c.wi, frame.n, v.hit.ng) * std::abs(q.wo.z) / std::abs(cosX);
  }
  ++rays;
  const Ray ray = shadowRay(v.hit, c.wi, c.distance);
  if (!throughPanes) {
    if (scene.occluded(ray)) return false;
  } else {
    const Color through = scene.transmittance(ray);  // thin glass: its T
    if (!(maxComponent(through) > 0.0f)) return false;
    L *= through;
  }
  pixel = uint32_t(c.raster.y) * uint32_t(camera.width()) + uint32_t(c.raster.x);
  return true;
}

}  // namespace firstshot
