// Ray-bundle stochastic iteration: the image estimate per camera sample.
#include "render/integrators/bundle/integrator.h"

#include "common/util/interrupt.h"

namespace firstshot {

void BundleIntegrator::preprocess(const RenderScene& scene) {
  scene_ = &scene;
  firstShot_.build(scene);
  transfer_.build(scene, settings_, options_.comm, options_.maxDepth);
  seed_ = 0;
  const auto& lights = scene.lights().lights();
  neeLights_.assign(lights.size(), 0);
  anyNee_ = false;
  for (size_t l = 0; l < lights.size(); ++l) {
    neeLights_[l] = lights[l].replaced || lights[l].type != LightType::Area;
    anyNee_ = anyNee_ || neeLights_[l];
  }
}

void BundleIntegrator::beginPass(int sampleIndex, uint64_t seed) const {
  const uint64_t k = uint64_t(std::max(0, sampleIndex));
  if (seed != seed_ || transfer_.iterations() > k + 1) {
    transfer_.reset();
    seed_ = seed;
  }
  // Resuming at a late index replays every iteration; SIGINT/SIGTERM stops the replay (render()
  // then stops too, and a later call continues from where it stopped). An iteration is collective
  // over the MPI ranks: they stop together, when any has the signal.
  Comm* comm = options_.comm && options_.comm->size() > 1 ? options_.comm : nullptr;
  auto stop = [&] { return comm ? comm->any(interrupted()) : interrupted(); };
  while (transfer_.iterations() <= k && !stop()) transfer_.iterate(seed);
}

Color BundleIntegrator::surface(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf, int vertex,
                                Sampler& sampler, uint64_t& rays) const {
  if (woLocal.z == 0.0f) return Color(0.0f);
  const BundleTransfer& t = transfer_;
  const uint32_t e = t.elements().index(hit);
  const int side = woLocal.z > 0.0f ? 0 : 1;
  const Color fIn = bsdf.eval(BSDFQuery(frame.toLocal(t.incomingDirection(t.elements()[e].normal, side)), woLocal));
  const bool exact = options_.primary == PrimaryMode::Exact;
  // Light that arrives after b reflections makes b + 1 bounces at this vertex: b ≤ D − 1 − vertex.
  const Color in = t.incoming(e, side, options_.maxDepth - 1 - vertex);
  Color L = (2.0f * kPiF) * fIn * (exact ? in : in + t.incomingPoint(e, side));
  if (exact) {
    if (anyNee_) {
      NeeRequest o;
      o.kept = o.replaced = true;
      o.mis = false;  // the bundle never carries these lights' emission: no other technique counts them
      o.tableVisibility = scene_->firstShot() && options_.tableVisibility;
      L += nextEventEveryLight(*scene_, firstShot_, &neeLights_, hit, frame, woLocal, bsdf, o, sampler, rays);
    }
    return L;
  }
  for (size_t d = 0; d < t.directionalLights().size(); ++d) {
    const Color& E = t.directionalIrradiance(d, e);
    if (maxComponent(E) <= 0.0f) continue;
    const Vec3 wi = -scene_->lights().lights()[t.directionalLights()[d]].direction;
    L += bsdf.eval(BSDFQuery(frame.toLocal(wi), woLocal)) * E;
  }
  if (scene_->firstShot() && hit.onPatch()) L += firstShot_.eval(hit, frame, woLocal, bsdf);
  return L;
}

Color BundleIntegrator::Li(const Ray& cameraRay, Sampler& sampler, SampleInfo* info) const {
  const RenderScene& scene = *scene_;
  uint64_t rays = 0;
  Color L(0.0f), beta(1.0f);
  Ray ray = cameraRay;
  for (int depth = 0;; ++depth) {
    Hit hit;
    ++rays;
    if (!scene.intersect(ray, hit)) break;
    const Vec3 wo = -glm::normalize(ray.d);
    if (!hit.onPatch()) L += beta * scene.lights().emitted(hit, wo);  // seen directly or via delta bounces
    const BSDF bsdf = scene.bsdfAt(hit);
    if (info && depth == 0) {
      info->albedo = bsdf.albedo();
      info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
    }
    // Vertex `depth` scatters (reflects the transfer's light, takes NEE, follows a mirror) only below
    // the max depth; its emission above counts up to it (docs/irradiance-cache.md, "What --max-depth counts").
    if (depth >= options_.maxDepth || maxComponent(bsdf.albedo()) <= 0.0f) break;
    const Frame frame = scene.shadingFrame(hit);  // not flipped: the dielectric needs the outward normal
    const Vec3 woLocal = frame.toLocal(wo);
    if (!bsdf.hasDelta() && !bsdf.hasTransmission()) {  // rough glass is followed as glass is
      L += beta * surface(hit, frame, woLocal, bsdf, depth, sampler, rays);
      break;
    }
    BSDFQuery q(woLocal);
    const Color weight = bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) break;
    beta *= weight;
    const Vec3 wi = frame.toWorld(q.wi);
    ray = Ray(hit.spawnOrigin(wi), wi);
  }
  if (info) info->rays = rays;
  return L;
}

}  // namespace firstshot
