// Irradiance caching: the shading of camera and gather paths, and the primary method.
#include "render/integrators/irradiance_cache/integrator.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "common/sampling/sampling.h"
#include "common/util/interrupt.h"
#include "render/integrators/irradiance_cache/context.h"
#include "render/integrators/irradiance_cache/hemisphere_samples.h"
#include "render/scene/embree_scene.h"
#include "render/scene/table_rows.h"
#include "render/scene/thin_glass_walk.h"

namespace firstshot {

namespace {

/// A 64-bit identity of a first-shot table (its factors decide the gathered radiance).
uint64_t tableHash(const FirstShotTable& t) {
  Hasher h;
  h.add(t.sceneHash).add(t.settings.hash()).add(hashPatches(t.mesh));
  for (const LightSample& s : t.samples) h.add(s.kind).add(s.light).add(s.position).add(s.normal).add(s.emission).add(s.weight);
  TableRows::hash(t, h);
  return h.value();
}

}  // namespace

IrradianceCacheIntegrator::IrradianceCacheIntegrator(const IntegratorOptions& options, const IrradianceCacheSettings& settings)
    : options_(options), settings_(settings) {}

IrradianceCacheIntegrator::~IrradianceCacheIntegrator() = default;

float IrradianceCacheIntegrator::accuracy(int level) const {
  return settings_.accuracy * std::pow(1.4f, float(level));
}

int IrradianceCacheIntegrator::strata(int level) const {
  const double n = std::max(8.0, std::ldexp(double(std::max(1, settings_.samples)), -level));
  return std::max(2, int(std::lround(std::sqrt(n / 2.0))));
}

std::unique_ptr<IrradianceCache> IrradianceCacheIntegrator::makeCache() const {
  std::vector<float> a;
  for (int l = 0; l < settings_.bounces; ++l) a.push_back(accuracy(l));
  return std::make_unique<IrradianceCache>(boundsLo_, boundsHi_, std::move(a));
}

std::string IrradianceCacheIntegrator::settingsText() const {
  std::string gathered;
  for (size_t l = 0; l < gathered_.size(); ++l)
    if (gathered_[l]) {
      if (!gathered.empty()) gathered += ',';
      gathered += std::to_string(l);
    }
  const FirstShotTable* t = scene_ ? scene_->firstShot() : nullptr;
  return fmt::format(
      "accuracy={} samples={} bounces={} past-last={} ambient={},{},{} gradients={} clamp-footprint={},{} neighbour-clamp={} "
      "max-depth={} levels=path-vertices gathered-lights=[{}] firstshot={} patch-nee={} luminaires={}",
      settings_.accuracy, settings_.samples, settings_.bounces, settings_.pathContinuation ? "path" : "ambient", settings_.ambient.x, settings_.ambient.y,
      settings_.ambient.z, settings_.gradients ? "on" : "off", settings_.footprintMin, settings_.footprintMax,
      settings_.neighbourClamp ? "on" : "off", options_.maxDepth, gathered, t ? fmt::format("{:016x}", tableHash(*t)) : "none",
      patchNeeOn() ? fmt::format("{}", settings_.patchNee) : "off",
      luminaires_ ? std::to_string(scene_->luminaires().items().size()) : "off");
}

std::vector<IntegratorRecord> IrradianceCacheIntegrator::records() const {
  std::vector<IntegratorRecord> out;
  if (!cache_ || cache_->levels() == 0) return out;
  for (const IrradianceRecord& r : cache_->records(0)) out.push_back({r.p, r.n, accuracy(0) * r.radius()});
  return out;
}

IrradianceCacheStats IrradianceCacheIntegrator::stats() const {
  IrradianceCacheStats s;
  s.loaded = loaded_;
  if (cache_)
    for (int l = 0; l < cache_->levels(); ++l) s.perLevel.push_back(cache_->size(l)), s.records += s.perLevel.back();
  s.privateRecords = privateRecords_.load();
  s.missPaths = missPaths_.load();
  s.fillSeconds = fillSeconds_;
  s.fillCutAt = fillCutAt_;
  s.fillPixels = fillTasks_;
  s.fillRays = fillRays_;
  s.fillRounds = fillRounds_;
  s.fillMade = madeRecords_;
  s.fillDuplicates = duplicateRecords_;
  s.exchangeBytes = exchangeBytes_;
  s.exchangeSeconds = exchangeSeconds_;
  return s;
}

Color IrradianceCacheIntegrator::LiFrom(const Ray& ray, const Hit* first, Sampler& sampler, SampleInfo* info,
                                        uint64_t& rays) const {
  Context ctx(frozen_ ? Context::Mode::Private : Context::Mode::Shared);
  ctx.rays = rays;
  const Color L = radiance(ray, 0, RayKind::Camera, 0.0f, sampler, ctx, nullptr, info, first);
  if (ctx.overlay) privateRecords_ += ctx.overlay->size();
  rays = ctx.rays;
  return L;
}

Color IrradianceCacheIntegrator::radiance(Ray ray, int level, RayKind kind, float pathLength, Sampler& sampler,
                                          Context& ctx, FirstVertex* first, SampleInfo* info, const Hit* known) const {
  const RenderScene& scene = *scene_;
  const LightSet& lights = scene.lights();
  Color L(0.0f), beta(1.0f);
  bool cameraChain = kind == RayKind::Camera;  // only mirrors and glass since the camera
  float prevPdf = 0.0f;
  Vec3 prevP(0.0f);
  if (first) *first = FirstVertex{std::numeric_limits<float>::infinity(), Hit(), Color(0.0f)};
  const LuminaireBoxes& boxes = scene.luminaires();
  int inside = luminaires_ ? boxes.containing(ray.o) : -1;  // the luminaire box the ray leaves from, or −1

  for (int depth = 0;; ++depth) {
    // The hit's place along the whole path, counted as the path tracer counts (its vertex index,
    // docs/irradiance-cache.md, "What --max-depth counts"), and the cache level it reads and makes
    // records at: a record's gather is that vertex's bounce, mirrors, glass and glossy samples are too.
    const int vertex = level + depth;
    Hit hit;
    BSDF bsdf;
    if (!nextHitPastPanes(scene, ray, known, sampler, beta, ctx.rays, hit, bsdf)) {  // a pane crossed is no bounce
      // The sky or environment map is direct light at every vertex (NEE, weight 1): only the camera's rays and
      // those past mirrors and glass count it where they leave the scene.
      if (kind == RayKind::Camera || kind == RayKind::Delta) L += beta * lights.background(glm::normalize(ray.d));
      break;
    }
    if (depth == 0 && first) first->distance = hit.t, first->hit = hit;
    pathLength += hit.t;
    if (luminaires_) {
      const int now = boxes.containing(hit.p);
      if (now >= 0 && now != inside && (kind == RayKind::Gather || kind == RayKind::Glossy)) {
        L += enteredLuminaire(ray, hit, bsdf, beta, vertex, sampler, ctx, depth == 0 ? first : nullptr);
        break;
      }
      inside = now;
    }
    const Vec3 wo = -glm::normalize(ray.d);

    if (!hit.onPatch()) {  // an area light
      const Color Le = lights.emitted(hit, wo);
      if (maxComponent(Le) > 0.0f) {
        const bool gathered = gatheredEmitter_[hit.emitter];
        if (kind == RayKind::Camera || kind == RayKind::Delta || (gathered && kind == RayKind::Gather))
          L += beta * Le;  // nothing else counts it
        else if (gathered && kind == RayKind::Glossy)
          L += beta * Le * powerHeuristic(prevPdf, lights.pdf(lights.emitterLight(hit.emitter), prevP, hit.p, hit.ng));
        // else: a small light met by a cache or BSDF ray is direct light, counted at the vertex
      }
    }

    if (info && depth == 0) {
      info->albedo = bsdf.albedo();
      info->normal = glm::dot(hit.ng, wo) >= 0.0f ? hit.ng : -hit.ng;
    }
    if (vertex >= options_.maxDepth || maxComponent(bsdf.albedo()) <= 0.0f) break;  // emission only there
    const Frame frame = scene.shadingFrame(hit);  // a shaded point is path-traced (not isDiffuse)
    const Vec3 woLocal = frame.toLocal(wo);

    if (bsdf.hasDelta()) {  // mirror or glass: follow the sampled lobe
      BSDFQuery q(woLocal);
      const Color w = bsdf.sample(q, sampler.next2D());
      if (!(q.pdf > 0.0f) || !(maxComponent(w) > 0.0f)) break;
      beta *= w;
      kind = RayKind::Delta;
      const Vec3 wi = frame.toWorld(q.wi);
      ray = Ray(hit.spawnOrigin(wi), wi);
      continue;
    }

    L += beta * shade(hit, frame, woLocal, bsdf, vertex, cameraChain, pathLength, sampler, ctx,
                      depth == 0 && first ? &first->firstShot : nullptr);
    if (bsdf.isDiffuse()) break;

    // The non-diffuse part f − ρd/π: NEE + MIS for the gathered lights, then one BSDF sample.
    NeeRequest o;
    o.kept = o.replaced = true;
    o.nonDiffuseOnly = true;
    L += beta * nextEventEveryLight(scene, firstShot_, &gathered_, hit, frame, woLocal, bsdf, o, sampler, ctx.rays);
    BSDFQuery q(woLocal);
    bsdf.sample(q, sampler.next2D());
    if (!(q.pdf > 0.0f)) break;
    Color f = bsdf.eval(q);
    if (q.wi.z * q.wo.z > 0.0f) f = glm::max(f - bsdf.diffuseAlbedo() * kInvPiF, Color(0.0f));
    const Color w = f * (std::abs(q.wi.z) / q.pdf);
    if (!(maxComponent(w) > 0.0f)) break;
    beta *= w;
    kind = RayKind::Glossy;
    cameraChain = false;
    prevPdf = q.pdf;
    prevP = hit.p;
    const Vec3 wi = frame.toWorld(q.wi);
    ray = Ray(hit.spawnOrigin(wi), wi);
  }
  return L;
}

Color IrradianceCacheIntegrator::shade(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                                       int level, bool cameraVertex, float pathLength, Sampler& sampler,
                                       Context& ctx, Color* firstShot) const {
  const bool useTable =
      scene_->firstShot() && hit.onPatch() && !(options_.primary == PrimaryMode::Exact && cameraVertex);
  Color L(0.0f);
  if (useTable) {
    const Color fs = firstShot_.eval(hit, frame, woLocal, bsdf);
    if (firstShot) *firstShot = fs;
    L += fs;
  }
  if (cameraVertex) {
    // What the camera sees keeps its direct light from NEE to every direct light: no cache averages
    // it there, and one light per sample (the tree) left 4x the noise of the image mean on many-lights.
    NeeRequest o;
    o.kept = true;
    o.replaced = !useTable;
    o.mis = false;  // cache and BSDF rays never count the direct lights
    o.infinite = true;  // nor the sky
    o.tableVisibility = scene_->firstShot() && options_.tableVisibility;
    // With luminaires: their exit patches and specular light, one sample of each luminaire's, and their lights where
    // the path tracer samples them (inside a box seen as it is; for the light that leaves a box straight from them).
    L += nextEventEveryLight(*scene_, firstShot_, innerLightsAt(hit.p) ? &direct_ : &directEvery_, hit, frame, woLocal,
                             bsdf, o, sampler, ctx.rays);
    if (luminaires_) L += nextEventEveryLuminaire(directLights_, hit, frame, woLocal, bsdf, o, sampler, ctx.rays);
  } else {
    // Inside gathers the hemisphere averages many vertices: the light sampler (--light-sampler).
    NeeRequest nee;  // the direct lights (directLights_ holds no others), replaced ones where the table is not used
    nee.kept = true;
    nee.replaced = !useTable;  // only off the patches: no table visibility there
    nee.mis = false;
    nee.infinite = true;
    nee.inner = innerLightsAt(hit.p);
    L += nextEvent(directLights_, hit, frame, woLocal, bsdf, nee, sampler, ctx.rays);
  }
  const Color rho = bsdf.diffuseAlbedo();
  if (maxComponent(rho) > 0.0f) {
    const Vec3 n = woLocal.z >= 0.0f ? hit.ng : -hit.ng;  // the viewer's side
    L += rho * kInvPiF * irradiance(hit, n, level, pathLength, sampler, ctx);
  }
  return L;
}

Color IrradianceCacheIntegrator::irradiance(const Hit& hit, const Vec3& n, int level, float pathLength,
                                            Sampler& sampler, Context& ctx) const {
  // E = π·L(ω) for ω distributed as cosθ/π: one path, with every light this vertex counted
  // (direct_) weighted 0 where the path meets it, everything else counted from the next hit on.
  auto pathIrradiance = [&](Sampler& from) {
    const Vec3 w = Frame(n).toWorld(squareToCosineHemisphere(from.next2D()));
    PathVertex prev;
    prev.delta = false;
    prev.p = hit.p;
    prev.n = n;
    prev.pdf = squareToCosineHemispherePdf(Vec3(0.0f, 0.0f, glm::dot(w, n)));
    prev.counted = &direct_;
    prev.countedInfinite = true;
    prev.countedExits = true;
    return kPiF *
           continuation_.trace(Ray(hit.spawnOrigin(w), w), Color(1.0f), level + 1, prev, false, from, ctx.rays);
  };
  if (level >= settings_.bounces)
    return settings_.pathContinuation ? pathIrradiance(sampler) : kPiF * settings_.ambient;
  // Drawn whether or not a record is made, so that the path does not depend on the cache.
  const uint64_t key = sampler.nextBits();
  IrradianceEstimate est;
  const int32_t zone = zoneOf(hit.p);
  ++ctx.lookups;
  cache_->lookup(level, hit.p, n, settings_.gradients, est, 1.0f, zone);
  if (ctx.overlay) ctx.overlay->lookup(level, hit.p, n, settings_.gradients, est, 1.0f, zone);
  if (est.count > 0) return est.value();
  if (frozen_) {  // two-pass render: a point the fill did not reach; first try the doubled domains
    cache_->lookup(level, hit.p, n, settings_.gradients, est, 2.0f, zone);
    if (est.count > 0) return est.value();
    // One path instead of a record private to this sample, whose hundreds of rays (and deeper private
    // records) would serve it only; unbiased, as past the last level.
    if (pathOnMiss_ && settings_.pathContinuation) {
      ++missPaths_;
      if (missSalt_ == 0) return pathIrradiance(sampler);
      Sampler keyed = Sampler::fromKey(hashKeys(key, missSalt_));
      return pathIrradiance(keyed);
    }
  } else if (pathOnMiss_ && taskRayBudget_ > 0 && ctx.rays > taskRayBudget_ && settings_.pathContinuation) {
    return pathIrradiance(sampler);  // a fill task over its budget
  }

  Sampler rs = Sampler::fromKey(key);
  IrradianceRecord r = gather(hit, n, level, pathLength, rs, ctx);
  if (level == 0 && spreadEvery_ > 0 && key % uint64_t(spreadEvery_) == 0) {
    // The pilot's measure of the records' own noise: the same record gathered again with other numbers, the records
    // its deeper lookups make kept to its own context; neither its rays nor its records count.
    Context other(Context::Mode::Private);
    Sampler os = Sampler::fromKey(hashKeys(key, kSpreadSalt));
    const Color again = gather(hit, n, level, pathLength, os, other).E;
    r.spread = glm::abs(r.E - again) * float(1.0 / std::sqrt(2.0));
  }
  if (ctx.mode == Context::Mode::Shared) {
    cache_->insert(level, r, settings_.neighbourClamp);
  } else {
    if (!ctx.overlay) ctx.overlay = makeCache();
    if (settings_.neighbourClamp) cache_->clampToNeighbours(level, r);  // the shared cache is read-only here
    ctx.overlay->insert(level, r, settings_.neighbourClamp);
  }
  return r.E;
}

IrradianceRecord IrradianceCacheIntegrator::computeRecord(const Hit& hit, const Vec3& n, int level, Sampler& sampler,
                                                          float pathLength) const {
  Context ctx(Context::Mode::Private);
  return gather(hit, n, level, pathLength, sampler, ctx);
}

IrradianceRecord IrradianceCacheIntegrator::gather(const Hit& hit, const Vec3& n, int level, float pathLength,
                                                   Sampler& sampler, Context& ctx) const {
  // SIGINT/SIGTERM: a record can take long (its rays make deeper records); stop before each. The
  // camera sample in progress is dropped whole (the film holds only finished samples).
  throwIfInterrupted();
  const int M = strata(level), N = 2 * M;
  const Frame frame(n);
  HemisphereSamples hs(M, N);
  const uint64_t key = sampler.nextBits();
  const bool nee = patchNeeOn() && level + 1 < options_.maxDepth;  // the rays' hits (vertex level + 1) count first-shot terms
  Vec3d overlap(0.0);  // Σ (1 − w_h)·first-shot radiance of the rays: what patch NEE takes over
  for (int j = 0; j < M; ++j)
    for (int k = 0; k < N; ++k) {
      const Vec3 local = squareToCosineHemisphereStratum(j, k, M, N, sampler.next2D());
      const Vec3 w = frame.toWorld(local);
      Sampler ps = Sampler::fromKey(hashKeys(key, uint64_t(j * N + k)));
      FirstVertex first;
      hs.L(j, k) = radiance(Ray(hit.spawnOrigin(w), w), level + 1, RayKind::Gather, pathLength, ps, ctx, &first, nullptr);
      hs.r(j, k) = first.distance;
      if (nee && maxComponent(first.firstShot) > 0.0f)
        overlap += Vec3d(first.firstShot) * double(1.0f - hemisphereWeight(hit.p, n, M * N, first.hit, local.z));
    }

  IrradianceRecord rec;
  rec.p = hit.p;
  rec.zone = zoneOf(hit.p);
  rec.n = n;
  hs.estimate(frame, settings_.gradients, rec);  // E, R and gradients from the rays' full radiance
  if (nee) {
    // E = π/(MN) Σ (L − (1 − w_h)·L_fs) + patch NEE; the gradients stay the hemisphere rays' own.
    const Vec3d E = Vec3d(rec.E) - overlap * (kPi / double(M * N)) + Vec3d(patchNeeIrradiance(hit, n, M * N, key, ctx));
    rec.E = Color(glm::max(E, Vec3d(0.0)));
  }
  rec.R = std::min(rec.R, cache_ ? cache_->extent() : rec.R);
  if (settings_.gradients)  // R_i ≤ E_i/|∇t E_i| (Křivánek et al.): the linear change stays below E_i
    for (int c = 0; c < 3; ++c) {
      const float g = glm::length(rec.gradT[c]);
      if (g > 0.0f && rec.E[c] > 0.0f) rec.R = std::min(rec.R, rec.E[c] / g);
    }
  if (pathLength > 0.0f && pixelAngle_ > 0.0f) {
    // The valid domain a·R_i in [min, max] pixel footprints.
    const float footprint = pixelAngle_ * pathLength / accuracy(level);
    rec.Rmin = settings_.footprintMin * footprint;
    rec.Rmax = std::max(rec.Rmin, settings_.footprintMax * footprint);
  }
  return rec;
}

}  // namespace firstshot
