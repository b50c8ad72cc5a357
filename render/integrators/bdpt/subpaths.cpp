// Camera and light subpaths of bidirectional path tracing.
#include "render/integrators/bdpt/subpaths.h"

#include <algorithm>

namespace fs {

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

  Ray ray = cameraRay;
  Color beta(1.0f);  // W_e·cosθ/pdf = 1 for the pixel the ray goes through
  for (int depth = 1; depth <= maxHits; ++depth) {
    Hit hit;
    ++rays;
    if (!scene.intersect(ray, hit)) break;
    SubpathVertex v;
    v.hit = hit;
    v.wi = -glm::normalize(ray.d);
    v.beta = beta;
    v.material = scene.material(hit);
    const BSDF bsdf = scene.bsdfAt(hit);
    v.delta = bsdf.hasDelta();
    path.push_back(v);
    if (depth >= maxHits || maxComponent(bsdf.albedo()) <= 0.0f) break;

    const Frame frame(hit.ng);
    BSDFQuery q(frame.toLocal(v.wi));
    const Color weight = bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) break;
    const Vec3 wi = frame.toWorld(q.wi);
    beta *= weight;
    ray = Ray(hit.spawnOrigin(wi), wi);
    if (depth >= rrDepth) {
      const float survive = std::min(0.95f, maxComponent(beta));
      if (!(sampler.next1D() < survive)) break;
      beta /= survive;
    }
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
    } else {
      v.delta = lv.delta;
    }
    out.push_back(v);
  }
  if (out.empty()) return;
  out[0].pdfFwd = densities.pdfOrigin(out[0]);
  densities.setDensities(out);
}

}  // namespace fs
