// The random walk of camera and light subpaths: the next hit, then BSDF sampling and Russian roulette.
#include "render/integrators/common/subpath_walk.h"

#include <algorithm>
#include <cmath>

#include "render/scene/thin_glass_walk.h"

namespace firstshot {

bool SubpathWalk::next(uint64_t& rays, Sampler& sampler) {
  if (++depth_ > settings_.maxHits) return false;
  const Hit* known = nullptr;
  if (!nextHitPastPanes(*scene_, ray_, known, sampler, beta_, rays, hit_, bsdf_)) return false;
  material_ = scene_->material(hit_);
  return true;
}

bool SubpathWalk::scatter(const Vec3& wi, Sampler& sampler) {
  pdf_ = 0.0f;
  if (depth_ >= settings_.maxHits || maxComponent(bsdf_.albedo()) <= 0.0f) return false;
  const Frame frame = scene_->shadingFrame(hit_);
  BSDFQuery q(frame.toLocal(wi), settings_.mode);
  const Color weight = bsdf_.sample(q, sampler.next2D());
  if (!(q.pdf > 0.0f) || !(maxComponent(weight) > 0.0f)) return false;
  pdf_ = q.pdf;
  const Vec3 w = frame.toWorld(q.wi);
  beta_ *= weight;
  if (settings_.mode == TransportMode::Importance && bsdf_.shaded())  // a particle: Veach's adjoint factor
    beta_ *= adjointCorrection(wi, w, frame.n, hit_.ng);
  ray_ = Ray(hit_.spawnOrigin(w), w);
  if (depth_ >= settings_.rrDepth) {
    const float ratio = maxComponent(beta_) / settings_.start;
    const float survive = std::min(0.95f, settings_.sqrtSurvival ? std::sqrt(ratio) : ratio);
    if (!(sampler.next1D() < survive)) return false;
    beta_ /= survive;
  }
  return true;
}

}  // namespace firstshot
