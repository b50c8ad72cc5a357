// Patch NEE in the irradiance cache's primary method: the lit first-shot patches sampled as area
// emitters at the record point, combined with the hemisphere rays by the power heuristic.
//
// Two techniques estimate the first-shot part of E = ∫ L cosθ dω: the record's MN stratified
// hemisphere rays (density cosθ/π per ray, each stratum's density being MN·cosθ/π over 1/MN of
// the hemisphere) and K patch NEE samples (density p_l, samplePatchEmitter, render/lights/next_event.h). With
// multi-sample MIS each technique weights its own samples by
//   w_h = (MN·cosθ/π)² / ((MN·cosθ/π)² + (K·p_l)²),   w_l = 1 − w_h at the same direction,
// so E = π/(MN) Σ_rays (L − (1 − w_h)·L_fs) + (1/K) Σ_samples w_l·L_fs·cosθ/p_l is unbiased:
// w_h + w_l = 1 wherever a patch emits, and w_h = 1 where NEE cannot find the hit (p_l = 0).
// The stratified selection of the NEE samples ((i + u)/K for the tree) keeps each sample's
// weight a function of its direction only.
#include <algorithm>
#include <cmath>

#include "render/integrators/irradiance_cache/context.h"
#include "render/integrators/irradiance_cache/integrator.h"

namespace firstshot {

namespace {

constexpr uint64_t kNeeStream = ~uint64_t(0);  ///< key of the NEE samples' sampler (the rays use 0 .. MN−1)

/// Power heuristic of @p a against @p b (effective densities: count × density).
inline double power2(double a, double b) { return a * a + b * b > 0 ? a * a / (a * a + b * b) : 0.0; }

/// NEE samples of a record of @p cells hemisphere rays.
int neeSampleCount(float ratio, int cells) { return std::max(1, int(std::lround(double(ratio) * cells))); }

}  // namespace

bool IrradianceCacheIntegrator::patchNeeOn() const {
  return scene_ && scene_->firstShot() && settings_.patchNee > 0.0f && directLights_.hasPatchEmitters();
}



float IrradianceCacheIntegrator::hemisphereWeight(const Vec3& x, const Vec3& n, int cells, const Hit& y,
                                                  float cosTheta) const {
  NeeRequest request;
  request.patches = true;
  const double pl = nextEventPdf(directLights_, x, n, request, y);
  if (!(pl > 0.0)) return 1.0f;
  const int K = neeSampleCount(settings_.patchNee, cells);
  return float(power2(double(cells) * double(cosTheta) * kInvPi, double(K) * pl));
}

Color IrradianceCacheIntegrator::patchNeeIrradiance(const Hit& hit, const Vec3& n, int cells, uint64_t key,
                                                    Context& ctx) const {
  const int K = neeSampleCount(settings_.patchNee, cells);
  Sampler s = Sampler::fromKey(hashKeys(key, kNeeStream));
  Vec3d sum(0.0);
  for (int i = 0; i < K; ++i) {
    const Vec2 uv = s.next2D();
    const float uSelect = std::min((float(i) + s.next1D()) / float(K), 0x1.fffffep-1f);
    PatchSample ps;
    if (!samplePatchEmitter(directLights_, hit.p, n, Vec3(uSelect, uv), ps)) continue;
    const float cosTheta = glm::dot(ps.wi, n);
    if (!(cosTheta > 0.0f)) continue;  // below the record's hemisphere: no irradiance
    ++ctx.rays;
    const Color through = scene_->transmittance(shadowRay(hit, ps.wi, ps.distance));  // thin glass: its T
    if (!(maxComponent(through) > 0.0f)) continue;
    const double wl = 1.0 - power2(double(cells) * double(cosTheta) * kInvPi, double(K) * double(ps.pdf));
    sum += Vec3d(ps.Le * through) * (wl * double(cosTheta) / double(ps.pdf));
  }
  return Color(sum / double(K));
}

}  // namespace firstshot
