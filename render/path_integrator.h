#pragma once
/// @file path_integrator.h
/// Unidirectional path tracing with next-event estimation to every light, multiple importance
/// sampling (power heuristic) against BSDF sampling for area lights, and Russian roulette.
///
/// With a first-shot table (RenderScene::firstShot), the table's small lights leave light
/// sampling and emission: every non-delta vertex on patch j adds
///     Σ_i emission_i · r_ij · f_r(ω'_i, x, ω)
/// with ω'_i the direction from x to light sample i (against the travel direction for
/// directional lights). The BSDF's side test makes a sample on the other side of the patch than
/// the viewer contribute nothing. Large lights keep NEE + MIS. A small area light met by a path
/// is counted only where the first-shot term could not have counted it: seen by the camera,
/// after a delta bounce (mirror, glass), or from a vertex that sampled it by NEE (PrimaryMode::Exact).
#include <vector>

#include "render/direct_light.h"
#include "render/integrator.h"

namespace fs {

class PathIntegrator : public Integrator {
 public:
  explicit PathIntegrator(const IntegratorOptions& options) : options_(options) {}
  /// Keeps the scene and, with a first-shot table, sums each patch's factors per side of its
  /// plane: on a Lambertian patch the first-shot term is then ρ/π times one of two irradiances.
  void preprocess(const RenderScene& scene) override;
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  std::string name() const override { return "path"; }

  /// The first-shot radiance reflected at a hit on patch hit.patch towards the local @p wo.
  Color firstShot(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const;

 private:
  /// NEE to every light (skipping the small ones when @p skipReplaced), with MIS for area lights.
  Color directLight(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf, bool skipReplaced,
                    Sampler& sampler, uint64_t& rays) const;

  IntegratorOptions options_;
  const RenderScene* scene_ = nullptr;
  FirstShotLighting firstShot_;
};

}  // namespace fs
