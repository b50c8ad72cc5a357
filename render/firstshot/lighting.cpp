// The first-shot term of a table at a hit point (render/firstshot/lighting.h).
#include "render/firstshot/lighting.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/lights/spot_integral.h"
#include "common/sampling/sampling.h"
#include "common/table/firstshot_groups.h"

namespace firstshot {

namespace {

/// The kernel k_i(x) of a point light, spot or area-light vertex at @p x with unit normal @p n,
/// cosθ_x taken on the side @p sign (±1) of the plane: W/m² per unit emission. @p spot is the
/// sample's normalised profile for a spot (profile/∫profile), unused otherwise. @p wi receives the
/// unit direction to the sample.
inline float sampleKernel(const LightSample& s, const SpotKernel& spot, const Vec3& x, const Vec3& n, float sign,
                          Vec3& wi) {
  const Vec3 d = s.position - x;
  const float d2 = glm::dot(d, d);
  if (!(d2 > 0.0f)) return 0.0f;
  const float inv = 1.0f / std::sqrt(d2);
  wi = d * inv;
  const float cosX = sign * glm::dot(wi, n);
  if (!(cosX > 0.0f)) return 0.0f;
  if (s.kind == LightSampleKind::Point) return cosX * inv * inv * (1.0f / (4.0f * kPiF));
  if (s.kind == LightSampleKind::Spot) return cosX * inv * inv * spot(-wi);
  const float cosL = -glm::dot(wi, s.normal);
  return cosL > 0.0f ? s.weight * cosX * cosL * inv * inv : 0.0f;
}

/// Gradient of the kernel with respect to x (m⁻¹ per unit of the kernel's value, W/m³ per unit
/// emission), for n on the lit side: point (1/4π)(−n/ρ³ + 3(n·r)r/ρ⁵), area vertex
/// w(−(−nL·r)n/ρ⁴ + (n·r)nL/ρ⁴ + 4(n·r)(−nL·r)r/ρ⁶), with r = position − x, ρ = |r|; 0 where the
/// kernel is 0.
Vec3d kernelGradient(const LightSample& s, const Vec3d& x, const Vec3d& n) {
  const Vec3d r = Vec3d(s.position) - x;
  const double rho2 = glm::dot(r, r), cosN = glm::dot(n, r);
  if (!(rho2 > 0) || !(cosN > 0)) return Vec3d(0.0);
  const double rho = std::sqrt(rho2);
  if (s.kind == LightSampleKind::Point)
    return (-n / (rho2 * rho) + 3.0 * cosN * r / (rho2 * rho2 * rho)) / (4.0 * kPi);
  const Vec3d nL(s.normal);
  const double cosL = -glm::dot(nL, r);
  if (!(cosL > 0)) return Vec3d(0.0);
  const double rho4 = rho2 * rho2;
  return double(s.weight) * (-cosL * n / rho4 + cosN * nL / rho4 + 4.0 * cosN * cosL * r / (rho4 * rho2));
}

/// Gradient of a spot's kernel (sampleKernel) with respect to x by central differences in double
/// precision, steps of 10⁻⁴ of the distance to the light: W/m³ per unit emission.
Vec3d spotKernelGradient(const LightSample& s, const SpotKernel& spot, const Vec3d& x, const Vec3d& n) {
  auto k = [&](const Vec3d& y) {
    const Vec3d r = Vec3d(s.position) - y;
    const double rho2 = glm::dot(r, r), cosN = glm::dot(n, r);
    if (!(rho2 > 0) || !(cosN > 0)) return 0.0;
    const double rho = std::sqrt(rho2);
    return cosN / (rho2 * rho) * spot.profile(-r / rho) * spot.invIntegral;
  };
  const double h = 1e-4 * glm::length(Vec3d(s.position) - x);
  if (!(h > 0) || !(k(x) > 0)) return Vec3d(0.0);
  Vec3d g;
  for (int a = 0; a < 3; ++a) {
    Vec3d e(0.0);
    e[a] = h;
    g[a] = (k(x + e) - k(x - e)) / (2.0 * h);
  }
  return g;
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
  // A deterministic function of the scene: its integrators share one build (render/scene/scene_memo.h).
  scene_ = &scene;
  d_ = scene.memo().find<Data>("FirstShotLighting");
  if (d_) return;
  d_ = compute(scene);
  scene.memo().keep("FirstShotLighting", d_);
}

std::shared_ptr<const FirstShotLighting::Data> FirstShotLighting::compute(const RenderScene& scene) {
  const auto data = std::make_shared<Data>();
  Data& d = *data;
  const FirstShotTable* t = scene.firstShot();
  if (!t) return data;
  d.rows_ = TableRows(*t);
  const uint32_t n = t->mesh.size();
  d.side_.assign(2 * size_t(n), SideTerm());
  d.visible_.assign(d.rows_.factors(), -1.0f);
  d.spots_.assign(t->samples.size(), SpotKernel());
  for (size_t i = 0; i < t->samples.size(); ++i)
    if (t->samples[i].kind == LightSampleKind::Spot) {
      SpotKernel& k = d.spots_[i];
      k.profile = EmissionProfile(scene.desc().lights[t->samples[i].light]);
      k.invIntegral = k.profile.integral() > 0 ? float(1.0 / k.profile.integral()) : 0.0f;
    }
  std::vector<uint8_t> near(d.rows_.factors(), 0);
  const bool haveVisible = d.rows_.hasStoredVisible();
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t j) {
    const Patch& p = t->mesh.patches[j];
    Vec3d poly[4];
    double diameter = 0;
    for (uint32_t k = 0; k < p.count; ++k) poly[k] = Vec3d(p.v[k]);
    for (uint32_t k = 0; k < p.count; ++k)
      for (uint32_t l = k + 1; l < p.count; ++l) diameter = std::max(diameter, glm::length(poly[l] - poly[k]));
    const Vec3d c(p.centroid), normal = glm::normalize(Vec3d(p.normal));
    Vec3d gradient[2][3] = {};
    for (const TableFactor f : d.rows_[j]) {
      const uint64_t k = f.index;
      const LightSample& s = t->samples[f.sample];
      const int side = sampleSide(s, p);
      if (side < 0) continue;
      // V_ij = r_ij A_j / (scale_i U_ij): points and area vertices by the preprocessor's closed forms
      // (as the reader already did, if it did), spots by their integrated kernel.
      double v = -1.0;
      if (s.kind == LightSampleKind::Spot) {
        const SpotKernel& spot = d.spots_[f.sample];
        const double scaledU = spotPatchIntegral(s, spot.profile, p, side) * spot.invIntegral;
        v = scaledU > 0 ? double(f.r) * p.area / scaledU : -1.0;
      } else if (s.kind != LightSampleKind::Directional) {
        v = haveVisible ? d.rows_.storedVisible(k) : recoveredVisible(f.r, s, t->areaEyeOffset, p);
      }
      if (v >= 0 && v <= kMaxVisible) {
        d.visible_[k] = float(v);
        if (glm::length(Vec3d(s.position) - c) < kNearPatches * diameter) {
          near[k] = 1;
          continue;
        }
        const Vec3d nSide = side == 0 ? normal : -normal;
        Vec3d g = v * (s.kind == LightSampleKind::Spot ? spotKernelGradient(s, d.spots_[f.sample], c, nSide)
                                                       : kernelGradient(s, c, nSide));
        g -= glm::dot(g, normal) * normal;  // in the plane
        for (int ch = 0; ch < 3; ++ch) gradient[side][ch] += double(s.emission[ch]) * g;
      }
      d.side_[2 * size_t(j) + side].average += s.emission * f.r;
    }
    for (int side = 0; side < 2; ++side)
      for (int ch = 0; ch < 3; ++ch) d.side_[2 * size_t(j) + side].gradient[ch] = Vec3(gradient[side][ch]);
  });
  d.visibilityMap_.build(*t, d.visible_, scene.desc().lights);
  d.nearSpotStart_.assign(size_t(n) + 1, 0);
  for (uint32_t j = 0; j < n; ++j) {
    for (const TableFactor f : d.rows_[j]) {
      const uint64_t k = f.index;
      if (!near[k]) continue;
      const LightSample& s = t->samples[f.sample];
      if (s.kind == LightSampleKind::Spot)
        d.nearSpot_.push_back(k);
      else if (s.kind == LightSampleKind::Point)
        d.near_.addPoint(s.position, s.emission * (d.visible_[k] / (4.0f * kPiF)));
      else
        d.near_.addArea(s.position, s.normal, s.emission * (d.visible_[k] * s.weight));
    }
    d.near_.endPatch();
    d.nearSpotStart_[j + 1] = d.nearSpot_.size();
  }
  return data;
}

Color FirstShotLighting::irradiance(const Hit& hit, bool front) const {
  const Data& d = *d_;
  const FirstShotTable& t = *scene_->firstShot();
  const SideTerm& far = d.side_[2 * size_t(hit.patch) + (front ? 0 : 1)];
  const Vec3 dx = hit.p - t.mesh.patches[hit.patch].centroid;
  Color e = far.average + Color(glm::dot(dx, far.gradient[0]), glm::dot(dx, far.gradient[1]), glm::dot(dx, far.gradient[2]));
  e = glm::max(e, Color(0.0f));
  const float sign = front ? 1.0f : -1.0f;
  e += d.near_.sum(hit.patch, hit.p, hit.ng * sign);
  for (uint64_t m = d.nearSpotStart_[hit.patch], end = d.nearSpotStart_[hit.patch + 1]; m < end; ++m) {
    const TableFactor f = d.rows_.at(d.nearSpot_[m]);
    const LightSample& s = t.samples[f.sample];
    Vec3 wi;
    e += s.emission * (d.visible_[f.index] * sampleKernel(s, d.spots_[f.sample], hit.p, hit.ng, sign, wi));
  }
  return e;
}

Color FirstShotLighting::eval(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const {
  const Data& d = *d_;
  if (bsdf.isDiffuse()) {
    // f = ρ/π for every sample on the viewer's side, 0 for the others.
    const bool front = woLocal.z > 0.0f;
    const Color f = bsdf.eval(BSDFQuery(Vec3(0.0f, 0.0f, front ? 1.0f : -1.0f), woLocal));
    return f * irradiance(hit, front);
  }
  // Other BSDFs depend on each sample's direction: one term per factor, per point where V_ij is known.
  auto weight = [&](const TableFactor& factor, const LightSample& s, Vec3& wi, float& e) {
    const float v = d.visible_[factor.index];
    if (!(v >= 0.0f)) return true;  // the patch average r_ij
    // The kernel on the sample's side of the plane.
    const float sign = glm::dot(s.position - hit.p, hit.ng) >= 0.0f ? 1.0f : -1.0f;
    e = v * sampleKernel(s, d.spots_[factor.sample], hit.p, hit.ng, sign, wi);
    return e > 0.0f;
  };
  if (bsdf.shaded()) {
    // A shading normal (a diffuse one too: BSDF::isDiffuse is false): the factors' irradiance is about
    // the geometric normal, the reflected radiance about the shading one, so each term is weighted by
    // |ω'_i·n_s|/|ω'_i·n_g| (the BSDF's side test drops samples the two normals disagree on).
    auto shadedWeight = [&](const TableFactor& factor, const LightSample& s, Vec3& wi, float& e) {
      if (!weight(factor, s, wi, e)) return false;
      const float cosG = std::abs(glm::dot(wi, hit.ng));
      e *= cosG > 0.0f ? std::abs(glm::dot(wi, frame.n)) / cosG : 0.0f;
      return e > 0.0f;
    };
    return sumReflectedFirstShot(scene_->firstShot()->samples, d.rows_[hit.patch], hit.p, frame, woLocal, bsdf,
                                 FirstShotProduct::EmissionLast, Color(0.0f), shadedWeight);
  }
  return sumReflectedFirstShot(scene_->firstShot()->samples, d.rows_[hit.patch], hit.p, frame, woLocal, bsdf,
                               FirstShotProduct::EmissionLast, Color(0.0f), weight);
}

}  // namespace firstshot
