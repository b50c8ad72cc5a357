#pragma once
/// @file integrator.h
/// Unidirectional path tracing: a sampling integrator over the path walk
/// (render/integrators/common/path_walk.h: NEE, MIS, the first-shot term, Russian roulette), which
/// builds the scene's first-shot lighting once and traces each camera ray's path with it.
#include <string>

#include "render/firstshot/lighting.h"
#include "render/integrators/integrator.h"
#include "render/integrators/common/path_walk.h"

namespace fs {

class PathIntegrator : public Integrator {
 public:
  explicit PathIntegrator(const IntegratorOptions& options) : options_(options) {}
  /// Keeps the scene, sums each patch's first-shot factors per side of its plane, and builds the
  /// walk (its light sampler: light trees, patch emitters).
  void preprocess(const RenderScene& scene) override;
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  /// Traces the block's camera rays as one Embree packet (3× the rays per second of single rays).
  void LiBlock(const Ray* rays, const bool* traced, const bool* wanted, int count, Sampler* samplers,
               SampleInfo* infos, Color* L) const override;
  std::string name() const override { return "path"; }
  bool supportsSensors() const override { return true; }

  /// The walk each camera ray's path takes (after preprocess()).
  const PathWalk& walk() const { return walk_; }

 private:
  IntegratorOptions options_;
  const RenderScene* scene_ = nullptr;
  FirstShotLighting lighting_;  ///< the walk's (built once per preprocess())
  PathWalk walk_;
};

}  // namespace fs
