#pragma once
/// @file light_tracer.h
/// Light tracing (particle tracing with connections to the camera): the shooting estimator of the
/// adjoint identity <L, W_e> = <L_e, W> (Dutré et al., docs/light-tracing.md).
///
/// Each pass traces particlesPerPass() = width·height light subpaths (render/integrators/light/
/// light_path.h). Every vertex that can reach the pinhole — an area light's vertex 0 and every
/// non-delta surface vertex — is connected to it by a shadow ray and splats
///     beta · f(ω_light, ω_camera) · |cosθ_x| · W_e·cosθ_c/d²  / N
/// into the pixel it projects to (CameraConnection: the same box filter as the jittered camera
/// rays of the gathering integrators), N the particles of the pass. The pass's splat sums are one
/// sample of every pixel, so the film's mean and variance are per pass.
///
/// Paths a pinhole cannot close from the light side are gathered instead, per pixel, in Li():
/// camera samples whose first hit is a delta surface (mirror, glass) take the path tracer's
/// estimate; the splats skip them (they start from non-delta vertices only), so the two parts
/// partition the pixel's paths. Point and spot lights are not seen by the camera (as in gathering).
/// With a first-shot table the table's small lights are shot like the others (shooting is exact
/// without the table); only the path-traced delta pixels read the table.
#include <vector>

#include "render/integrator.h"
#include "render/integrators/light/light_path.h"
#include "render/integrators/path.h"
#include "render/light_emission.h"

namespace fs {

class LightTracingIntegrator : public Integrator {
 public:
  explicit LightTracingIntegrator(const IntegratorOptions& options) : options_(options), fallback_(options) {}
  void preprocess(const RenderScene& scene) override;
  /// The camera-side part of a sample: the AOVs, and the path tracer's radiance for a ray whose
  /// first hit is a delta surface; 0 otherwise (the splats carry it).
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  std::string name() const override { return "light"; }

  bool splats() const override { return true; }
  uint64_t particlesPerPass(const Camera& camera) const override {
    return uint64_t(camera.width()) * uint64_t(camera.height());
  }
  void splatParticles(const Camera& camera, uint64_t seed, uint64_t pass, uint64_t begin, uint64_t end,
                      std::vector<Splat>& out, uint64_t& rays) const override;

  /// The splat of light-path vertex @p v to the camera, unscaled by 1/N: false if it cannot
  /// reach the pinhole (delta, behind the camera, off the film, occluded, or on the far side).
  /// @p pixel receives y·width + x. @p rays counts the shadow ray.
  bool connect(const LightVertex& v, const Camera& camera, uint32_t& pixel, Color& L, uint64_t& rays) const;

  const EmissionSampler& emission() const { return emission_; }
  LightPathOptions pathOptions() const { return {options_.maxDepth, options_.rrDepth}; }

  /// The stream index of the particles' samplers: Sampler(seed, particle, pass, kParticleStream).
  static constexpr uint64_t kParticleStream = 0x4c54;  // "LT"

 private:
  IntegratorOptions options_;
  const RenderScene* scene_ = nullptr;
  EmissionSampler emission_;
  PathIntegrator fallback_;  ///< for camera rays whose first hit is a delta surface
};

}  // namespace fs
