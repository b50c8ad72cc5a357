// The path-tracing walk: NEE + MIS + Russian roulette, the first-shot term for small lights and
// the lit patches as sampled emitters.
#include "render/integrators/common/path_walk.h"

#include <algorithm>
#include <cmath>

#include "render/integrators/common/path_recorder.h"
#include "render/scene/thin_glass_walk.h"

namespace firstshot {

namespace {

/// A glossy lobe: neither Lambertian nor delta (a rough conductor, pbr, Phong, rough glass).
bool isGlossy(const BSDF& bsdf) {
  return !bsdf.hasDelta() && !std::holds_alternative<LambertBRDF>(bsdf.model());
}

}  // namespace

void PathWalk::build(const RenderScene& scene, const FirstShotLighting& lighting, const IntegratorOptions& options) {
  options_ = options;
  scene_ = &scene;
  lighting_ = &lighting;
  lights_.build(scene, lighting, options_.lightSampler, options_.patchNee != PatchNee::Off, options_.lightVisibility,
                nullptr, false, options_.luminaires);
}

void PathWalk::enterLuminaires(const Ray& piece, float tEnd, const Color& beta, const PathVertex& prev,
                               const LuminaireState& state, Color& L) const {
  const LuminaireBoxes& boxes = scene_->luminaires();
  LuminaireBoxes::Entry entries[LuminaireBoxes::kMaxEntries];
  // A little past the hit: a hit on a box's face is inside it (Luminaire::contains), so its entry must be seen.
  const float tmax = std::isinf(tEnd) ? tEnd : tEnd * (1.0f + 1e-5f) + 1e-6f;
  const int n = boxes.entries(piece.o, piece.d, tmax, entries);
  for (int i = 0; i < n; ++i) {
    const LuminaireBoxes::Entry& e = entries[i];
    if (e.t < piece.tmin) continue;  // an earlier piece's
    if (prev.delta) continue;  // seen as it is: its lights count where the path meets them
    if (prev.countedExits) continue;
    const Luminaire& lum = boxes.items()[e.luminaire];
    const Vec3 y = piece.o + e.t * piece.d;
    const Vec3 w = -glm::normalize(piece.d);
    const uint32_t k = lum.patchAt(e.face, y);
    const Color Le = lum.radianceAt(k, w);
    if (!(maxComponent(Le) > 0.0f)) continue;
    const float pdf = nextEventExitPdf(lights_, prev.p, prev.n, prev.nee, boxes.exitFirst(e.luminaire) + k, y);
    const Color c = beta * Le * (pdf > 0.0f ? powerHeuristic(prev.pdf, pdf) : 1.0f);
    L += c;
    if (PathRecorder* recorder = threadPathRecorder()) recorder->record(state.depth, PathTerm::ExitHit, PathVia::Direct, c);
  }
}

float PathWalk::emissionWeight(const PathVertex& prev, const Hit& hit) const {
  if (prev.delta) return 1.0f;  // no light sampling could have found it
  if (!hit.onPatch()) {
    const LightSet& lights = scene_->lights();
    const RenderLight& light = lights.emitterLight(hit.emitter);
    if (light.replaced && prev.usedTable) return 0.0f;  // the first-shot term of prev holds it
    if (prev.counted && (*prev.counted)[size_t(&light - lights.lights().data())]) return 0.0f;
  }
  const float pdf = nextEventPdf(lights_, prev.p, prev.n, prev.nee, hit);
  return pdf > 0.0f ? powerHeuristic(prev.pdf, pdf) : 1.0f;
}

Color PathWalk::escaped(const PathVertex& prev, const Vec3& dir) const {
  const EnvironmentMap* env = scene_->lights().environment();
  if (!env || prev.countedInfinite) return Color(0.0f);
  const Vec3 d = glm::normalize(dir);
  // The camera or a mirror: no light sampling could have found this direction (a sky: its model, not the map).
  if (prev.delta) return scene_->lights().background(d);
  const Color Le = env->radiance(d);
  const float pdf = nextEventEnvironmentPdf(lights_, prev.nee, d);
  return pdf > 0.0f ? Le * powerHeuristic(prev.pdf, pdf) : Le;
}

Color PathWalk::trace(Ray ray, Color beta, int depth, PathVertex prev, bool specularChain, Sampler& sampler,
                      uint64_t& rays, SampleInfo* info, const Hit* first) const {
  const RenderScene& scene = *scene_;
  // A table without replaced lights (its lights all in luminaires) adds nothing: no first-shot term to look up.
  const bool haveTable = scene.firstShot() != nullptr && !scene.firstShot()->replacedLights.empty();
  bool sampledPatches = false;  // a vertex of this path sampled the lit patches (PatchNee::First: once)
  Color L(0.0f);
  // The calling thread's recorder (path_recorder.h), null but for reports, and for it what the path passed after its
  // first non-delta vertex (PathVia), counted from where this walk starts.
  PathRecorder* const recorder = threadPathRecorder();
  bool pastNonDelta = false;
  PathVia via = PathVia::Direct;
  // Luminaires (render/scene/luminaire_boxes.h): the box the path is in, and whether its light was counted on entry.
  const bool useLuminaires = lights_.hasLuminaires();
  const LuminaireBoxes& boxes = scene.luminaires();
  LuminaireState lum;
  if (useLuminaires) lum.inside = boxes.containing(ray.o);

  for (;; ++depth) {
    Hit hit;
    BSDF bsdf;
    bool found;
    bool enteredBox = false;  // this segment entered a luminaire's box from outside (its hit is the first inside)
    if (useLuminaires) {
      lum.depth = depth;
      found = nextHitPastPanes(scene, ray, first, sampler, beta, rays, hit, bsdf,
                               [&](const Ray& piece, float tEnd, const Color& b) {
                                 enterLuminaires(piece, tEnd, b, prev, lum, L);
                               });
      const int now = found ? boxes.containing(hit.p) : -1;
      // A segment that enters a box from outside meets its lights, if at all, straight from a vertex outside: direct
      // light, which no exit distribution holds (counted below, weighted against NEE to the lights).
      enteredBox = now >= 0 && now != lum.inside;
      if (now < 0) lum.suppressed = false;
      else if (enteredBox) lum.suppressed = !prev.delta;  // entered: counted there, unless seen as it is
      lum.inside = now;
    } else {
      found = nextHitPastPanes(scene, ray, first, sampler, beta, rays, hit, bsdf);
    }
    if (!found) {  // a pane crossed is no bounce
      // The sky or environment map (through the panes crossed: beta has their T).
      const Color Le = beta * escaped(prev, ray.d);
      L += Le;
      if (recorder) recorder->record(depth, PathTerm::Environment, via, Le);
      break;
    }
    const Vec3 wo = -glm::normalize(ray.d);

    // Emission of area lights met by the path.
    if (!hit.onPatch()) {
      const Color Le = scene.lights().emitted(hit, wo);
      const bool counted =  // a luminaire's light met after a bounce in the box entered where its exit light counted
          lum.suppressed && !enteredBox &&
          boxes.ofLight(uint32_t(&scene.lights().emitterLight(hit.emitter) - scene.lights().lights().data())) ==
              lum.inside;
      if (maxComponent(Le) > 0.0f && !counted) {
        const Color c = beta * Le * emissionWeight(prev, hit);
        L += c;
        if (recorder)
          recorder->record(depth, scene.lights().emitterLight(hit.emitter).replaced ? PathTerm::SmallLightHit
                                                                                  : PathTerm::LargeLightHit,
                           via, c);
      }
    }

    if (info && depth == 0) {
      info->albedo = bsdf.albedo();
      info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
    }
    if (depth >= options_.maxDepth || maxComponent(bsdf.albedo()) <= 0.0f) break;

    // No flip: the BSDFs are two-sided and the dielectric needs the outward normal; the frame is the shading normal's.
    const Frame frame = scene.shadingFrame(hit);
    const Vec3 woLocal = frame.toLocal(wo);
    const bool useTable = haveTable && !(options_.primary == PrimaryMode::Exact && specularChain) &&
                          !bsdf.tooSharpForTable();  // a polished lobe: NEE to the replaced lights too
    NeeRequest nee;
    if (!bsdf.hasDelta()) {
      // What this vertex gathers passed a glossy lobe here if one came before it.
      const PathVia viaHere =
          recorder && pastNonDelta && via == PathVia::Direct && isGlossy(bsdf) ? PathVia::Glossy : via;
      // The first-shot term here is the emission of a lit patch, met from prev.
      if (useTable && hit.onPatch()) {
        const Color c = beta * firstShot(hit, frame, woLocal, bsdf) * emissionWeight(prev, hit);
        L += c;
        if (recorder) recorder->record(depth + 1, PathTerm::TableHit, viaHere, c);
      }
      nee.kept = true;
      nee.replaced = !useTable;
      // The luminaires' lights: inside a box seen as it is, and everywhere for the light that leaves a box straight
      // from them, but for the box this path entered from a non-delta vertex (its exit light holds theirs).
      nee.inner = useLuminaires && boxes.innerWanted(lum.inside, lum.suppressed);
      nee.exceptLuminaire = lum.suppressed ? lum.inside : -1;
      nee.tableVisibility = haveTable && options_.tableVisibility;
      nee.patches = lights_.hasPatchEmitters() && depth + 1 < options_.maxDepth &&  // a lit patch is one bounce more
                    (options_.patchNee == PatchNee::Every || !sampledPatches);
      sampledPatches = sampledPatches || nee.patches;
      NeeParts parts;
      L += beta * nextEvent(lights_, hit, frame, woLocal, bsdf, nee, sampler, rays, recorder ? &parts : nullptr);
      if (recorder) {
        recorder->record(depth + 1, PathTerm::LargeLightNee, viaHere, beta * parts.kept);
        recorder->record(depth + 1, PathTerm::SmallLightNee, viaHere, beta * parts.replaced);
        recorder->record(depth + 2, PathTerm::PatchNee, viaHere, beta * parts.patches);  // + the patch's reflection
        recorder->record(depth + 1, PathTerm::Environment, viaHere, beta * parts.environment);
      }
    }

    // Continue the path by sampling the BSDF.
    BSDFQuery q(woLocal);
    const Color weight = bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) break;
    const Vec3 wi = frame.toWorld(q.wi);
    if (recorder) {  // a delta bounce past a non-delta vertex makes a caustic; a glossy one past one, a glossy path
      if (pastNonDelta && q.specular) via = PathVia::Delta;
      else if (pastNonDelta && via == PathVia::Direct && isGlossy(bsdf)) via = PathVia::Glossy;
      pastNonDelta = pastNonDelta || !bsdf.hasDelta();
    }
    beta *= weight;
    prev.delta = q.specular;
    prev.usedTable = useTable;
    prev.pdf = q.pdf;
    prev.p = hit.p;
    prev.n = receiverNormal(bsdf, woLocal.z >= 0.0f ? hit.ng : -hit.ng);  // as nextEvent's
    prev.nee = nee;
    prev.counted = nullptr;
    prev.countedInfinite = false;
    prev.countedExits = false;
    specularChain = specularChain && q.specular;
    ray = Ray(hit.spawnOrigin(wi), wi);

    // Russian roulette on the throughput: survival √max(β) (as Cycles), not max(β). After three
    // bounces in a white room β ≈ 0.35, and a survivor weighted 1/0.35 was the largest part of the
    // path tracer's error on Cornell (the square root: rel. MSE at 256 spp −23%, for ≈ 8% more time).
    if (depth + 1 >= options_.rrDepth) {
      const float survive = std::min(0.95f, std::sqrt(maxComponent(beta)));
      if (!(sampler.next1D() < survive)) break;
      beta *= 1.0f / survive;
    }
  }
  return L;
}

}  // namespace firstshot
