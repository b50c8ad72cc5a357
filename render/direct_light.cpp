// NEE and the first-shot term, shared by the integrators.
#include "render/direct_light.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/analytic.h"

namespace fs {

Ray shadowRay(const Hit& hit, const Vec3& wi, float distance) {
  const float tmax = std::isinf(distance) ? distance : distance * (1.0f - 1e-4f) - hit.eps;
  return Ray(hit.spawnOrigin(wi), wi, 0.0f, tmax);
}

namespace {

/// The kernel k_i(x) of a point light or area-light vertex at @p x with unit normal @p n, cosθ_x
/// taken on the side @p sign (±1) of the plane: W/m² per unit emission. @p wi receives the unit direction to the sample.
inline float sampleKernel(const LightSample& s, const Vec3& x, const Vec3& n, float sign, Vec3& wi) {
  const Vec3 d = s.position - x;
  const float d2 = glm::dot(d, d);
  if (!(d2 > 0.0f)) return 0.0f;
  const float inv = 1.0f / std::sqrt(d2);
  wi = d * inv;
  const float cosX = sign * glm::dot(wi, n);
  if (!(cosX > 0.0f)) return 0.0f;
  if (s.kind == LightSampleKind::Point) return cosX * inv * inv * (1.0f / (4.0f * kPiF));
  const float cosL = -glm::dot(wi, s.normal);
  return cosL > 0.0f ? s.weight * cosX * cosL * inv * inv : 0.0f;
}

/// Which side of patch @p p's plane sample @p s lies on: 0 front, 1 back, −1 in the plane.
int sampleSide(const LightSample& s, const Patch& p) {
  const float side = s.kind == LightSampleKind::Directional ? -glm::dot(s.normal, p.normal)
                                                             : glm::dot(s.position - p.centroid, p.normal);
  return side > 0.0f ? 0 : side < 0.0f ? 1 : -1;
}

/// A visible fraction above this is not a fraction (a degenerate closed form): keep the average.
constexpr double kMaxVisible = 2.0;

}  // namespace

void FirstShotLighting::build(const RenderScene& scene) {
  scene_ = &scene;
  const FirstShotTable* t = scene.firstShot();
  sideAverage_.clear();
  visible_.clear();
  if (!t) return;
  const uint32_t n = t->mesh.size();
  sideAverage_.assign(2 * size_t(n), Color(0.0f));
  visible_.assign(t->factor.size(), -1.0f);
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t j) {
    const Patch& p = t->mesh.patches[j];
    Vec3d poly[4];
    for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
    for (uint64_t k = t->rowStart[j]; k < t->rowStart[j + 1]; ++k) {
      const LightSample& s = t->samples[t->sampleIndex[k]];
      double scaledU = 0;  // scale_i · U_ij
      if (s.kind == LightSampleKind::Point)
        scaledU = analytic::polygonSolidAngle(Vec3d(s.position), poly, int(p.count)) / (4.0 * kPi);
      else if (s.kind == LightSampleKind::AreaVertex)
        scaledU = s.weight * analytic::polygonCosineSolidAngle(Vec3d(s.position), glm::normalize(Vec3d(s.normal)), poly,
                                                               int(p.count));
      const double v = scaledU > 0 ? double(t->factor[k]) * p.area / scaledU : -1.0;
      if (v >= 0 && v <= kMaxVisible) {
        visible_[k] = float(v);
      } else if (const int side = sampleSide(s, p); side >= 0) {
        sideAverage_[2 * size_t(j) + side] += s.emission * t->factor[k];
      }
    }
  });
}

Color FirstShotLighting::irradiance(const Hit& hit, bool front) const {
  const FirstShotTable& t = *scene_->firstShot();
  Color e = sideAverage_[2 * size_t(hit.patch) + (front ? 0 : 1)];
  const float sign = front ? 1.0f : -1.0f;
  for (uint64_t k = t.rowStart[hit.patch], end = t.rowStart[hit.patch + 1]; k < end; ++k) {
    if (visible_[k] < 0.0f) continue;
    const LightSample& s = t.samples[t.sampleIndex[k]];
    Vec3 wi;
    e += s.emission * (visible_[k] * sampleKernel(s, hit.p, hit.ng, sign, wi));
  }
  return e;
}

Color FirstShotLighting::eval(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const {
  if (bsdf.isDiffuse()) {
    // f = ρ/π for every sample on the viewer's side, 0 for the others.
    const bool front = woLocal.z > 0.0f;
    const Color f = bsdf.eval(BSDFQuery(Vec3(0.0f, 0.0f, front ? 1.0f : -1.0f), woLocal));
    return f * irradiance(hit, front);
  }
  const FirstShotTable& t = *scene_->firstShot();
  Color sum(0.0f);
  for (uint64_t k = t.rowStart[hit.patch], end = t.rowStart[hit.patch + 1]; k < end; ++k) {
    const LightSample& s = t.samples[t.sampleIndex[k]];
    Vec3 wi = s.kind == LightSampleKind::Directional ? -s.normal : glm::normalize(s.position - hit.p);
    float e = t.factor[k];
    if (visible_[k] >= 0.0f) {  // per point: the kernel on the sample's side of the plane
      const float sign = glm::dot(s.position - hit.p, hit.ng) >= 0.0f ? 1.0f : -1.0f;
      e = visible_[k] * sampleKernel(s, hit.p, hit.ng, sign, wi);
      if (!(e > 0.0f)) continue;
    }
    const Color f = bsdf.eval(BSDFQuery(frame.toLocal(wi), woLocal));
    sum += s.emission * (e * f);
  }
  return sum;
}

Color estimateDirect(const RenderScene& scene, const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf,
                     const DirectLightOptions& options, Sampler& sampler, uint64_t& rays) {
  const LightSet& lights = scene.lights();
  const Color fDiffuse = options.nonDiffuseOnly ? bsdf.diffuseAlbedo() * kInvPiF : Color(0.0f);
  Color sum(0.0f);
  for (size_t l = 0; l < lights.lights().size(); ++l) {
    const RenderLight& light = lights.lights()[l];
    const Vec2 u = sampler.next2D();  // drawn for every light, so later dimensions do not shift
    if (options.skipReplaced && light.replaced) continue;
    if (options.include && !(*options.include)[l]) continue;
    LightRecord rec;
    if (!lights.sample(light, hit.p, u, rec)) continue;
    const BSDFQuery q(frame.toLocal(rec.wi), woLocal);
    Color f = bsdf.eval(q);
    if (options.nonDiffuseOnly && q.wi.z * q.wo.z > 0.0f) f = glm::max(f - fDiffuse, Color(0.0f));
    if (maxComponent(f) <= 0.0f) continue;
    ++rays;
    if (scene.occluded(shadowRay(hit, rec.wi, rec.distance))) continue;
    const float weight = light.isDelta() || !options.mis ? 1.0f : powerHeuristic(rec.pdf, bsdf.pdf(q));
    sum += f * (std::abs(q.wi.z) * weight) * rec.value;
  }
  return sum;
}

}  // namespace fs
