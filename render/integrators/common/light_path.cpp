// Light subpaths: emission, then adjoint BSDF sampling with Russian roulette.
#include "render/integrators/common/light_path.h"

#include <algorithm>
#include <cmath>

namespace fs {

bool traceLightPath(const RenderScene& scene, const EmissionSampler& emission, const LightPathOptions& options,
                    Sampler& sampler, std::vector<LightVertex>& path, uint64_t& rays, uint64_t stratum,
                    uint64_t strata) {
  path.clear();
  EmissionSample es;
  if (!emission.sample(sampler, es, stratum, strata)) return false;
  LightVertex v0;
  v0.hit.p = es.p;
  v0.hit.ng = es.n;
  v0.hit.eps = 1e-5f * (1.0f + maxComponent(glm::abs(es.p)));
  v0.beta = es.radiance;
  v0.pdfFwd = es.pdfLight * es.pdfPos;
  v0.pdfDir = es.pdfDir;
  v0.delta = es.deltaPosition || es.deltaDirection;
  v0.light = es.light;
  path.push_back(v0);

  Color beta = es.power;
  const float start = maxComponent(es.power);
  // A lit patch (table mode) is the particle's first bounce already: one vertex less, roulette one
  // bounce earlier.
  const int bounced = emission.isPatch(es.light) ? 1 : 0;
  const int maxDepth = options.maxDepth - bounced, rrDepth = options.rrDepth - bounced;
  Ray ray(es.deltaPosition || es.deltaDirection ? es.p : v0.hit.spawnOrigin(es.d), es.d);
  float pdfDir = es.pdfDir;
  bool deltaDir = es.deltaDirection;
  for (int depth = 1; depth <= maxDepth; ++depth) {
    Hit hit;
    ++rays;
    if (!scene.intersect(ray, hit)) break;
    LightVertex v;
    v.hit = hit;
    v.wi = -ray.d;
    v.beta = beta;
    const float cosIn = std::abs(glm::dot(hit.ng, ray.d));
    // A directional light's particles have a density per area across the beam: p_pos·|cosθ|.
    v.pdfFwd = deltaDir ? path.back().pdfFwd * cosIn : pdfDir * cosIn / (hit.t * hit.t);
    v.material = scene.material(hit);
    const BSDF bsdf = scene.bsdfAt(hit);
    v.delta = bsdf.hasDelta();
    path.push_back(v);
    if (depth >= maxDepth || maxComponent(bsdf.albedo()) <= 0.0f) break;
    if (depth == 1 && options.deltaFirstHitOnly && !v.delta) break;

    // Scatter: sample the adjoint BSDF with wo towards the light side.
    const Frame frame(hit.ng);
    BSDFQuery q(frame.toLocal(v.wi), TransportMode::Importance);
    const Color weight = bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) break;
    const Vec3 wo = frame.toWorld(q.wi);
    path.back().pdfDir = q.pdf;
    pdfDir = q.pdf;
    deltaDir = false;
    beta *= weight;
    ray = Ray(hit.spawnOrigin(wo), wo);

    if (depth >= rrDepth) {
      const float survive = std::min(0.95f, maxComponent(beta) / start);
      if (!(sampler.next1D() < survive)) break;
      beta /= survive;
    }
  }
  return true;
}

}  // namespace fs
