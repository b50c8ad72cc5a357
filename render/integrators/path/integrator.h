#pragma once
/// @file integrator.h
/// Unidirectional path tracing: a sampling integrator over the path walk
/// (render/integrators/common/path_walk.h: NEE, MIS, the first-shot term, Russian roulette), which
/// builds the scene's first-shot lighting once and traces each camera ray's path with it; a block's
/// camera rays are traced as one packet (render/integrators/common/packet_integrator.h).
#include <string>

#include "render/firstshot/lighting.h"
#include "render/integrators/common/packet_integrator.h"
#include "render/integrators/common/path_walk.h"

namespace firstshot {

class PathIntegrator : public PacketIntegrator {
 public:
  explicit PathIntegrator(const IntegratorOptions& options) : options_(options) {}
  /// Keeps the scene, sums each patch's first-shot factors per side of its plane, and builds the
  /// walk (its light sampler: light trees, patch emitters).
  void preprocess(const RenderScene& scene) override;
  std::string name() const override { return "path"; }
  bool supportsSensors() const override { return true; }
  /// The walk from the sensor's vertex @p from (not the camera: entering a luminaire's box counts its exit light).
  Color LiFromSensor(const Ray& ray, const PathVertex& from, Sampler& sampler, SampleInfo* info) const override;
  /// The walk's light sampler (after preprocess()).
  const LightSampler* lightSampler() const override { return &walk_.lightSampler(); }

  /// The walk each camera ray's path takes (after preprocess()).
  const PathWalk& walk() const { return walk_; }

 protected:
  /// The walk from the camera along @p ray.
  Color LiFrom(const Ray& ray, const Hit* first, Sampler& sampler, SampleInfo* info, uint64_t& rays) const override;

 private:
  IntegratorOptions options_;
  FirstShotLighting lighting_;  ///< the walk's (built once per preprocess())
  PathWalk walk_;
};

}  // namespace firstshot
