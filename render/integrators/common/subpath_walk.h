#pragma once
/// @file subpath_walk.h
/// The random walk of a subpath, hit after hit, shared by the light subpaths (light_path.h: light
/// tracing, BDPT) and BDPT's camera subpaths (render/integrators/bdpt/subpaths.h): next() traces to
/// the next hit, the caller records its vertex there, and scatter() samples the BSDF for the next
/// direction (the adjoint BSDF on a light subpath), multiplies the throughput by f·|cos θ|/pdf and
/// plays Russian roulette. Each walk keeps what its vertices need apart (densities, light indices).
#include <cstdint>

#include "common/materials/bsdf.h"
#include "common/sampling/rng.h"
#include "render/scene/ray.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// How a subpath walks.
struct SubpathWalkSettings {
  int maxHits = 16;  ///< hits at most; the walk does not scatter at the last one
  int rrDepth = 3;   ///< Russian roulette after scattering at hit number rrDepth and later ones
  /// The throughput the roulette measures against: survival min(0.95, √(max(beta)/start)) (or without
  /// the root, @ref sqrtSurvival); 1 on the camera side, the particle's emitted power on the light side.
  float start = 1.0f;
  TransportMode mode = TransportMode::Radiance;  ///< Importance on a light subpath
  /// √ survival (as the path walk: longer walks, less noise per walk; light tracing), or max(beta)/start
  /// (BDPT, whose cost grows with both subpaths' lengths: docs/measurements.md).
  bool sqrtSurvival = true;
};

class SubpathWalk {
 public:
  /// A walk along @p ray with throughput @p beta; @p scene must outlive it.
  SubpathWalk(const RenderScene& scene, const Ray& ray, const Color& beta, const SubpathWalkSettings& settings)
      : scene_(&scene), settings_(settings), ray_(ray), beta_(beta) {}

  /// Traces the current ray (counted in @p rays) unless maxHits hits are made; crosses the thin glass
  /// panes on the way (render/scene/thin_glass_walk.h, one dimension of @p sampler each), which are no
  /// hits of the walk. @return false if the walk ends (no hit, or no hit left).
  bool next(uint64_t& rays, Sampler& sampler);
  /// At the current hit, with @p wi the unit direction to the previous vertex: stops at the last
  /// hit or a black surface; else samples the BSDF (2 dimensions of @p sampler), updates the
  /// throughput and the ray, and from hit rrDepth on plays Russian roulette (1 dimension).
  /// @return false if the walk ends here.
  bool scatter(const Vec3& wi, Sampler& sampler);

  int depth() const { return depth_; }                ///< the current hit's number, 1 for the first
  const Hit& hit() const { return hit_; }             ///< the current hit
  const Ray& ray() const { return ray_; }             ///< the ray that reached it (after scatter(): the next one)
  const Color& beta() const { return beta_; }         ///< throughput arriving at the hit (after scatter(): leaving it)
  uint32_t material() const { return material_; }     ///< the hit's material
  const BSDF& bsdf() const { return bsdf_; }          ///< the hit's BSDF (its texture looked up)
  /// The solid-angle density of the direction the last scatter() sampled (1/sr; the discrete
  /// probability after a delta lobe), 0 if it sampled none.
  float pdf() const { return pdf_; }

 private:
  const RenderScene* scene_;
  SubpathWalkSettings settings_;
  Ray ray_;
  Color beta_;
  Hit hit_;
  int depth_ = 0;
  uint32_t material_ = kNoId;
  BSDF bsdf_;
  float pdf_ = 0.0f;
};

}  // namespace firstshot
