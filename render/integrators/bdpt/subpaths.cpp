// Camera and light subpaths of bidirectional path tracing.
#include "render/integrators/bdpt/subpaths.h"

#include "render/integrators/common/subpath_walk.h"

namespace firstshot {

void traceCameraPath(const BdptDensities& densities, const Ray& cameraRay, int maxHits, int rrDepth, Sampler& sampler,
                     std::vector<SubpathVertex>& path, uint64_t& rays) {
  const RenderScene& scene = densities.scene();
  path.clear();
  SubpathVertex v0;
  v0.kind = SubpathVertex::Kind::Camera;
  v0.hit.p = cameraRay.o;
  v0.beta = Color(1.0f);
  v0.pdfFwd = 1.0f;
  path.push_back(v0);

  // W_e·cosθ/pdf = 1 for the pixel the ray goes through.
  SubpathWalk walk(scene, cameraRay, Color(1.0f), {maxHits, rrDepth, 1.0f, TransportMode::Radiance, /*sqrtSurvival=*/false});
  while (walk.next(rays, sampler)) {
    SubpathVertex v;
    v.hit = walk.hit();
    v.wi = -glm::normalize(walk.ray().d);
    v.beta = walk.beta();
    v.material = walk.material();
    v.delta = walk.bsdf().hasDelta();
    path.push_back(v);
    if (!walk.scatter(v.wi, sampler)) break;
  }
  densities.setDensities(path);
}

void toBdptLightPath(const BdptDensities& densities, const std::vector<LightVertex>& in,
                     std::vector<SubpathVertex>& out) {
  out.clear();
  for (size_t k = 0; k < in.size(); ++k) {
    const LightVertex& lv = in[k];
    SubpathVertex v;
    v.hit = lv.hit;
    v.wi = lv.wi;
    v.beta = lv.beta;
    v.material = lv.material;
    if (k == 0) {
      v.kind = SubpathVertex::Kind::Light;
      v.light = lv.light;
      v.deltaLight = lv.delta;
      v.deltaDirection = densities.emission().isDirectional(lv.light);
      v.exitPatch = densities.emission().isExit(lv.light);
    } else {
      v.delta = lv.delta;
    }
    out.push_back(v);
  }
  if (out.empty()) return;
  out[0].pdfFwd = densities.pdfOrigin(out[0]);
  densities.setDensities(out);
}

}  // namespace firstshot
