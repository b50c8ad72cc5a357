#pragma once
/// @file path.h
/// Unidirectional path tracing with next-event estimation (render/light_sampler.h: NEE to every
/// light or one light chosen by a light tree), multiple importance sampling (power heuristic)
/// against BSDF sampling for area emitters, and Russian roulette.
///
/// With a first-shot table (RenderScene::firstShot), the table's small lights leave light
/// sampling and emission: every non-delta vertex on patch j adds
///     Σ_i emission_i · r_ij · f_r(ω'_i, x, ω)
/// (FirstShotLighting), and, with patch NEE (IntegratorOptions::patchNee), every non-delta vertex
/// also samples the lit patches as area emitters of that radiance: a BSDF-sampled path that meets
/// a lit patch weights its first-shot term against that by MIS, so nothing is counted twice.
/// Large lights keep NEE + MIS. A small area light met by a path is counted only where the
/// first-shot term could not have counted it: seen by the camera, after a delta bounce (mirror,
/// glass), or from a vertex that sampled it by NEE (PrimaryMode::Exact).
#include <vector>

#include "render/direct_light.h"
#include "render/firstshot/lighting.h"
#include "render/integrator.h"
#include "render/light_sampler.h"

namespace fs {

/// The vertex a path segment leaves from: what decides the weight of emission met at its end.
struct PathVertex {
  bool delta = true;        ///< the camera or a delta lobe: no light sampling could have found the next hit
  bool usedTable = false;   ///< the vertex took the replaced lights from the first-shot table
  float pdf = 0.0f;         ///< solid-angle density of the sampled direction
  Vec3 p{0.0f};             ///< position, m
  Vec3 n{0.0f};             ///< receiving normal passed to LightSampler (the viewer's side)
  NeeRequest nee;           ///< what the vertex sampled by NEE
  /// Lights (LightSet indices) the vertex counted in full by other means: they count 0 when met.
  const std::vector<uint8_t>* counted = nullptr;
};

class PathIntegrator : public Integrator {
 public:
  explicit PathIntegrator(const IntegratorOptions& options) : options_(options) {}
  /// Keeps the scene, sums each patch's first-shot factors per side of its plane, and builds the
  /// light sampler (light trees, patch emitters).
  void preprocess(const RenderScene& scene) override;
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  /// Traces the block's camera rays as one Embree packet (3× the rays per second of single rays).
  void LiBlock(const Ray* rays, const bool* traced, const bool* wanted, int count, Sampler* samplers,
               SampleInfo* infos, Color* L) const override;
  std::string name() const override { return "path"; }
  bool supportsSensors() const override { return true; }

  /// Radiance along @p ray times @p beta, for a path whose next hit is vertex number @p depth
  /// (0: seen from the camera) and leaves @p prev. @p specularChain: only delta bounces since the
  /// camera. @p rays counts the rays traced; @p info gets the AOVs of vertex 0. @p first, if given,
  /// is the closest hit of @p ray, already traced (and counted) by the caller.
  Color trace(Ray ray, Color beta, int depth, PathVertex prev, bool specularChain, Sampler& sampler, uint64_t& rays,
              SampleInfo* info = nullptr, const Hit* first = nullptr) const;

  /// The first-shot radiance reflected at a hit on patch hit.patch towards the local @p wo.
  Color firstShot(const Hit& hit, const Frame& frame, const Vec3& woLocal, const BSDF& bsdf) const {
    return firstShot_.eval(hit, frame, woLocal, bsdf);
  }
  const LightSampler& lightSampler() const { return lights_; }
  /// The lit patches' first-shot radiance (empty without a table), for integrators built on this one.
  const FirstShotLighting& lighting() const { return firstShot_; }

 private:
  /// Weight of emission met at @p hit (an area light or, for the first-shot term, a patch) by a
  /// segment from @p prev.
  float emissionWeight(const PathVertex& prev, const Hit& hit) const;

  IntegratorOptions options_;
  const RenderScene* scene_ = nullptr;
  FirstShotLighting firstShot_;
  LightSampler lights_;
};

}  // namespace fs
