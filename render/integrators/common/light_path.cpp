// Light subpaths: emission, then adjoint BSDF sampling with Russian roulette.
#include "render/integrators/common/light_path.h"

#include <cmath>

#include "render/integrators/common/subpath_walk.h"

namespace firstshot {

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

  const float start = maxComponent(es.power);
  // A lit patch (table mode) is the particle's first bounce already: one vertex less, roulette one
  // bounce earlier.
  const int bounced = emission.isPatch(es.light) ? 1 : 0;
  const int maxDepth = options.maxDepth - bounced, rrDepth = options.rrDepth - bounced;
  // A luminaire's light (with the exit particles): its box, which the particle's path ends by leaving after a
  // bounce off a non-delta surface inside it (the exit particles carry that light). A particle that leaves it straight
  // from the light, or after delta bounces only (through glass, off mirrors), goes on: neither light is in the exit
  // distribution.
  int inner = options.luminaires && es.light < emission.lightCount() ? options.luminaires->ofLight(es.light) : -1;
  if (!emission.splits(inner)) inner = -1;  // an unsplit luminaire's particles carry all its light
  const Luminaire* box = inner >= 0 ? &options.luminaires->items()[size_t(inner)] : nullptr;
  SubpathWalk walk(scene, Ray(es.deltaPosition || es.deltaDirection ? es.p : v0.hit.spawnOrigin(es.d), es.d), es.power,
                   {maxDepth, rrDepth, start, TransportMode::Importance, options.sqrtSurvival});
  float pdfDir = es.pdfDir;
  bool deltaDir = es.deltaDirection;
  bool scatteredInBox = false;  // a vertex inside the box was not a delta one
  while (walk.next(rays, sampler)) {
    const Hit& hit = walk.hit();
    if (box && !box->contains(hit.p)) {  // the segment left the box (convex: it cannot come back)
      if (scatteredInBox) break;         // the exit particles' light
      box = nullptr;                     // direct or specular: a room particle from here on
    }
    LightVertex v;
    v.hit = hit;
    v.wi = -walk.ray().d;
    v.beta = walk.beta();
    const float cosIn = std::abs(glm::dot(hit.ng, walk.ray().d));
    // A directional light's particles have a density per area across the beam: p_pos·|cosθ|.
    v.pdfFwd = deltaDir ? path.back().pdfFwd * cosIn : pdfDir * cosIn / (hit.t * hit.t);
    v.material = walk.material();
    v.delta = walk.bsdf().hasDelta();
    scatteredInBox = scatteredInBox || (box && !v.delta);
    path.push_back(v);
    if (walk.depth() == 1 && options.deltaFirstHitOnly && !(v.delta && !path[0].delta) &&
        !(options.polishedFirstHit && walk.bsdf().tooSharpForTable()))
      break;
    // Scatter: sample the adjoint BSDF with wo towards the light side.
    const bool more = walk.scatter(v.wi, sampler);
    path.back().pdfDir = pdfDir = walk.pdf();
    deltaDir = false;
    if (!more) break;
  }
  return true;
}

}  // namespace firstshot
