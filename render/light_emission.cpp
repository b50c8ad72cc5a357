// Emission sampling: a light by power, then a point and a direction.
#include "render/light_emission.h"

#include <algorithm>
#include <cmath>

#include "common/lights.h"
#include "common/sampling.h"

namespace fs {

namespace {

float mean(const Color& c) { return (c.x + c.y + c.z) / 3.0f; }

}  // namespace

EmissionSampler::EmissionSampler(const LightSet& lights, const SceneDesc& scene) : lights_(&lights) {
  Vec3d lo, hi;
  scene.bounds(lo, hi);
  centre_ = Vec3(0.5 * (lo + hi));
  radius_ = std::max(1e-6f, float(0.5 * glm::length(hi - lo)) * 1.01f);
  for (const RenderLight& l : lights.lights()) {
    double p = 0;
    switch (l.type) {
      case LightType::Point: p = 4.0 * kPi * mean(l.intensity); break;
      case LightType::Spot: p = mean(l.intensity) * spotProfileIntegral(l.desc); break;
      case LightType::Directional: p = mean(l.irradiance) * kPi * double(radius_) * radius_; break;
      case LightType::Area: p = mean(l.radiance) * l.area * kPi; break;
    }
    power_.push_back(std::max(0.0, p));
    total_ += power_.back();
  }
  double sum = 0;
  for (double p : power_) cdf_.push_back(total_ > 0 ? (sum += p) / total_ : 1.0);
  if (!cdf_.empty()) cdf_.back() = 1.0;
}

bool EmissionSampler::sampleOrigin(double u, const Vec2& uPos, EmissionSample& out) const {
  if (!(total_ > 0)) return false;
  const size_t l = std::min(size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()), cdf_.size() - 1);
  if (!(power_[l] > 0)) return false;
  const RenderLight& light = lights_->lights()[l];
  out = EmissionSample();
  out.light = static_cast<uint32_t>(l);
  out.pdfLight = float(power_[l] / total_);
  out.pdfPos = pdfPosition(light);
  switch (light.type) {
    case LightType::Point:
    case LightType::Spot:
      out.p = light.position;
      out.deltaPosition = true;
      break;
    case LightType::Directional: {
      const Frame frame(light.direction);
      const Vec2 disk = squareToUniformDiskConcentric(uPos) * radius_;
      out.p = centre_ - radius_ * light.direction + frame.s * disk.x + frame.t * disk.y;
      out.n = light.direction;
      out.d = light.direction;
      out.deltaDirection = true;
      break;
    }
    case LightType::Area:
      if (!lights_->samplePoint(light, uPos, out.p, out.n)) return false;
      out.radiance = light.radiance / (out.pdfLight * out.pdfPos);
      break;
  }
  return true;
}

float EmissionSampler::pdfPosition(const RenderLight& light) const {
  switch (light.type) {
    case LightType::Directional: return 1.0f / (kPiF * radius_ * radius_);
    case LightType::Area: return float(1.0 / light.area);
    default: return 1.0f;
  }
}

float EmissionSampler::pdfDirection(const RenderLight& light, const Vec3& n, const Vec3& d) const {
  switch (light.type) {
    case LightType::Point: return squareToUniformSpherePdf();
    case LightType::Spot: {
      const SpotCone cone(light.desc);
      return double(glm::dot(d, light.direction)) >= cone.cosOuter ? float(1.0 / (2.0 * kPi * (1.0 - cone.cosOuter)))
                                                                   : 0.0f;
    }
    case LightType::Area: return std::max(0.0f, glm::dot(n, d)) * kInvPiF;
    default: return 0.0f;
  }
}

bool EmissionSampler::sample(Sampler& sampler, EmissionSample& out) const {
  const double u = sampler.next1Dd();
  const Vec2 uPos = sampler.next2D();
  const Vec2 uDir = sampler.next2D();
  if (!sampleOrigin(u, uPos, out)) return false;
  const RenderLight& light = lights_->lights()[out.light];
  switch (light.type) {
    case LightType::Point: {
      out.d = squareToUniformSphere(uDir);
      out.pdfDir = squareToUniformSpherePdf();
      out.power = light.intensity / (out.pdfLight * out.pdfDir);
      break;
    }
    case LightType::Spot: {
      const SpotCone cone(light.desc);
      const float cosT = float(1.0 - double(uDir.x) * (1.0 - cone.cosOuter));
      const float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
      const float phi = 2.0f * kPiF * uDir.y;
      out.d = Frame(light.direction).toWorld(Vec3(sinT * std::cos(phi), sinT * std::sin(phi), cosT));
      out.pdfDir = float(1.0 / (2.0 * kPi * (1.0 - cone.cosOuter)));
      out.power = light.intensity * float(cone.profile(cosT)) / (out.pdfLight * out.pdfDir);
      break;
    }
    case LightType::Directional: {
      out.pdfDir = 1.0f;
      out.power = light.irradiance / (out.pdfLight * out.pdfPos);
      break;
    }
    case LightType::Area: {
      const Vec3 local = squareToCosineHemisphere(uDir);
      out.d = Frame(out.n).toWorld(local);
      out.pdfDir = squareToCosineHemispherePdf(local);
      if (!(out.pdfDir > 0.0f)) return false;
      out.power = out.radiance * (local.z / out.pdfDir);
      break;
    }
  }
  return maxComponent(out.power) > 0.0f;
}

}  // namespace fs
