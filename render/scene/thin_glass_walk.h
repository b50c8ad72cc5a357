#pragma once
/// @file thin_glass_walk.h
/// What a random walk does at a thin glass pane (common/materials/thin_glass.h): every walk of render/ (the
/// path tracer's, the irradiance cache's, light and camera subpaths) calls crossThinGlass at each hit on one.
#include <limits>

#include "common/materials/bsdf.h"
#include "common/sampling/rng.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// At a walk's hit on the pane @p glass, with @p u ∈ [0, 1): with probability P_T = mean(T)/mean(R + T)
/// (T, R the pane's at the hit's angle) the walk crosses it: @p beta *= T/P_T, @p ray starts again just
/// past the hit with the same origin and direction, and it returns true: trace @p ray again. The pane is
/// then no vertex of the path: the next hit's distance (and so its density) is measured from the path's
/// previous vertex, whose NEE already saw through the pane with its T (the shadow rays'
/// RenderScene::transmittance), so MIS weights and "the previous vertex" stay as they are. Otherwise it
/// returns false and @p bsdf becomes the pane's reflection alone, a mirror of tint R/(1 − P_T): a delta
/// vertex like any mirror's.
inline bool crossThinGlass(const ThinGlassBSDF& glass, const Hit& hit, float u, Ray& ray, Color& beta, BSDF& bsdf) {
  const float len = glm::length(ray.d);
  const float cosTheta = len > 0.0f ? std::abs(glm::dot(hit.ng, ray.d)) / len : 0.0f;
  Color R, T;
  glass.reflectTransmit(cosTheta, R, T);
  const float pT = ThinGlassBSDF::transmitProbability(R, T);
  if (u < pT) {
    beta *= T / pT;
    ray.tmin = hit.t + hit.eps / len;
    return true;
  }
  bsdf = MirrorBRDF{pT < 1.0f ? R / (1.0f - pT) : Color(0.0f)};
  return false;
}

/// A walk's next hit along @p ray with the panes it crosses on the way skipped (crossThinGlass at each, one
/// number of @p sampler a pane; @p beta and @p ray updated): the first candidate is @p *known when given
/// (then set to null: a hit the caller traced already), else traced (counted in @p rays). Fills @p hit and
/// @p bsdf (RenderScene::bsdfAt, or a pane's reflection). @return false if nothing is hit.
/// @p onPiece(ray, tEnd, beta), if given, is told each piece of the walk's segment before the pane at its end is
/// crossed: the ray from its tmin to @p tEnd (infinity past the last hit), and the throughput along it (what a
/// luminaire's exit light entered there is weighted with, render/scene/luminaire_boxes.h).
template <typename OnPiece>
inline bool nextHitPastPanes(const RenderScene& scene, Ray& ray, const Hit*& known, Sampler& sampler, Color& beta,
                             uint64_t& rays, Hit& hit, BSDF& bsdf, OnPiece&& onPiece) {
  for (;;) {
    if (known) {
      hit = *known;
      known = nullptr;
    } else {
      ++rays;
      if (!scene.intersect(ray, hit)) {
        onPiece(ray, std::numeric_limits<float>::infinity(), beta);
        return false;
      }
    }
    onPiece(ray, hit.t, beta);
    bsdf = scene.bsdfAt(hit);
    const ThinGlassBSDF* glass = bsdf.thinGlass();
    if (!glass || !crossThinGlass(*glass, hit, sampler.next1D(), ray, beta, bsdf)) return true;
  }
}

inline bool nextHitPastPanes(const RenderScene& scene, Ray& ray, const Hit*& known, Sampler& sampler, Color& beta,
                             uint64_t& rays, Hit& hit, BSDF& bsdf) {
  return nextHitPastPanes(scene, ray, known, sampler, beta, rays, hit, bsdf, [](const Ray&, float, const Color&) {});
}

}  // namespace firstshot
