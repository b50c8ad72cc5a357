// Path tracing with NEE + MIS + Russian roulette, and the first-shot term for small lights.
#include "render/path_integrator.h"

#include <algorithm>
#include <cmath>

namespace fs {

void PathIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  firstShot_.build(scene);
}

Color PathIntegrator::firstShot(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const {
  return firstShot_.eval(hit, frame, woLocal, bsdf);
}

Color PathIntegrator::directLight(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                                  bool skipReplaced, Sampler& sampler, uint64_t& rays) const {
  DirectLightOptions o;
  o.skipReplaced = skipReplaced;
  return estimateDirect(*scene_, hit, frame, woLocal, bsdf, o, sampler, rays);
}

Color PathIntegrator::Li(const Ray& cameraRay, Sampler& sampler, SampleInfo* info) const {
  const RenderScene& scene = *scene_;
  const LightSet& lights = scene.lights();
  const bool haveTable = scene.firstShot() != nullptr;
  uint64_t rays = 0;
  Color L(0.0f), beta(1.0f);
  Ray ray = cameraRay;
  bool specularChain = true;  // every vertex so far was a delta bounce (the camera counts as one)
  bool prevDelta = true;      // the last direction came from a delta lobe or the camera
  bool prevFirstShot = false; // the previous vertex took the small lights from the table
  float prevPdf = 0.0f;
  Vec3 prevP(0.0f);

  for (int depth = 0;; ++depth) {
    Hit hit;
    ++rays;
    if (!scene.intersect(ray, hit)) break;
    const Vec3 wo = -glm::normalize(ray.d);

    // Emission of area lights met by the path.
    if (!hit.onPatch()) {
      const Color Le = lights.emitted(hit.emitter, hit.ng, wo);
      if (maxComponent(Le) > 0.0f) {
        const RenderLight& light = lights.emitterLight(hit.emitter);
        if (prevDelta)
          L += beta * Le;  // no light sampling could have found it
        else if (!(light.replaced && prevFirstShot))
          L += beta * Le * powerHeuristic(prevPdf, lights.pdf(light, prevP, hit.p, hit.ng));
        // else: the first-shot term of the previous vertex already holds it
      }
    }

    const BSDF& bsdf = scene.bsdf(scene.material(hit));
    if (info && depth == 0) {
      info->albedo = bsdf.albedo();
      info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
    }
    if (depth >= options_.maxDepth || maxComponent(bsdf.albedo()) <= 0.0f) break;

    const Frame frame(hit.ng);  // no flip: the BSDFs are two-sided and the dielectric needs the outward normal
    const Vec3 woLocal = frame.toLocal(wo);
    const bool useTable = haveTable && !(options_.primary == PrimaryMode::Exact && specularChain);
    if (!bsdf.hasDelta()) {
      if (useTable && hit.onPatch()) L += beta * firstShot(hit, frame, woLocal, bsdf);
      L += beta * directLight(hit, frame, woLocal, bsdf, useTable, sampler, rays);
    }

    // Continue the path by sampling the BSDF.
    BSDFQuery q(woLocal);
    const Color weight = bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) break;
    const Vec3 wi = frame.toWorld(q.wi);
    beta *= weight;
    prevDelta = q.specular;
    prevPdf = q.pdf;
    prevP = hit.p;
    prevFirstShot = useTable;
    specularChain = specularChain && q.specular;
    ray = Ray(hit.spawnOrigin(wi), wi);

    // Russian roulette on the throughput.
    if (depth + 1 >= options_.rrDepth) {
      const float survive = std::min(0.95f, maxComponent(beta));
      if (!(sampler.next1D() < survive)) break;
      beta /= survive;
    }
  }
  if (info) info->rays = rays;
  return L;
}

}  // namespace fs
