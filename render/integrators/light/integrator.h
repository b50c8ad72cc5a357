#pragma once
/// @file integrator.h
/// Light tracing (particle tracing with connections to the camera): the shooting estimator of the
/// adjoint identity <L, W_e> = <L_e, W> (Dutré et al., docs/light-tracing.md).
///
/// Each pass traces particlesPerPass() = k·width·height light subpaths (render/integrators/common/
/// light_path.h), k = pathsPerPixel(), and one camera sample per pixel. Every vertex that can reach
/// the pinhole — an area light's vertex 0 and every non-delta surface vertex — is connected to it
/// by a shadow ray and splats
///     beta · f(ω_light, ω_camera) · |cosθ_x| · W_e·cosθ_c/d²  / N
/// into the pixel it projects to (connectToCamera, common/camera_splat.h; CameraConnection: the
/// same box filter as the jittered camera rays of the gathering integrators), N the particles of
/// the pass. The pass's splat sums are one sample of every pixel, so the film's mean and variance
/// are per pass.
///
/// Paths a pinhole cannot close from the light side are gathered instead, per pixel, in Li():
/// camera samples whose first hit is a delta surface (mirror, glass) or a polished patch
/// (BSDF::tooSharpForTable: a lobe a particle's connection would almost never meet) take the path
/// tracer's estimate (the path walk, common/path_walk.h, over the integrator's first-shot
/// lighting); the splats skip them (they start from the other vertices only), so the two parts
/// partition the pixel's paths. Point and spot lights are not seen by the camera (as in gathering).
///
/// With a first-shot table and IntegratorOptions::shootFromPatches (table mode) the small lights
/// are not shot: particles leave the kept lights and the lit patch sides (EmissionSampler's table
/// mode, common/shooting_emitters.h), so the table is the small lights' first bounce. A patch
/// particle's vertex 0 is not splatted, and its vertex k makes a path of k + 1 bounces. What the
/// small lights give the camera directly — their direct light at the first hit x (next-event
/// estimation, exact shadows, MIS with x's BSDF sample for area lights) and their emission seen at
/// x — comes from Li() per pixel (SmallLightsExact, common/lights/small_light_rule.h, shared with BDPT). A
/// small area light's light whose first bounce is a mirror or glass (no table holds it) comes from
/// a second particle per particle index when the scene has both: shot from the small area lights,
/// stopped at a first hit that is not delta. In a scene with polished surfaces (whose lit patches
/// emit nothing: render/firstshot/patch_emitters.h) that second particle leaves every small light
/// and also goes on from a polished first hit. This is the path space of the path tracer with the
/// same table and PrimaryMode::Exact. Without the option the table's small lights are shot like the
/// others (shooting is exact without the table), and only the path-traced delta pixels read the
/// table.
///
/// Luminaires (IntegratorOptions::luminaires and a table that has them, docs/luminaires.md; in either mode, as
/// their lights are kept lights): a luminaire's light reaches the room through its exit distribution. Particles also
/// leave the exit patches (EmissionSampler::addExits, chosen by power with the other emitters); their vertex 0, on
/// the exit patch in empty space, does not splat (the camera sees through the box's faces), every later vertex does,
/// and one that enters a box goes on (room light entering it). The luminaires' lights still emit their own particles,
/// which splat inside the box (the camera sees the inside of a shade as it is) and end where their path first leaves
/// it (LightPathOptions::luminaires). The two are estimators of disjoint sets of light paths (those that reach the
/// camera from inside the box before leaving it, and those from after), each unbiased with its particles' share of
/// the count. The delta pixels' path walk keeps the luminaires' lights as lights.
#include <vector>

#include "render/integrators/common/light_path.h"
#include "render/integrators/common/path_walk.h"
#include "render/integrators/common/shooting_integrator.h"
#include "render/lights/light_emission.h"

namespace firstshot {

// Declared like BdptIntegrator (bdpt/integrator.h), the shooting integrators' interface; their particles differ.
class LightTracingIntegrator : public ShootingIntegrator {
 public:
  using ShootingIntegrator::ShootingIntegrator;
  /// The shooting integrators' preprocess(), then the fallback walk over their lighting and the delta-first emitters.
  void preprocess(const RenderScene& scene) override;
  /// The camera-side part of a sample: the AOVs, and the path tracer's radiance for a ray whose
  /// first hit is a delta surface; otherwise, in table mode, the small lights' own part, and 0
  /// without a table (the splats carry it).
  Color Li(const Ray& ray, Sampler& sampler, SampleInfo* info = nullptr) const override;
  std::string name() const override { return "light"; }

  uint64_t particlesPerPass(const Camera& camera) const override {
    return uint64_t(pathsPerPixel(camera)) * uint64_t(camera.width()) * uint64_t(camera.height());
  }
  /// Light paths per pixel and pass for @p camera: IntegratorOptions::lightPathsPerPixel, or
  /// automatically 1 in a scene with mirrors or glass and otherwise kAutoPathsPerPixel, fewer where
  /// that would pass kAutoPathsPerPass (a pass's splats are held until it is summed). A camera
  /// sample costs about a light path; without mirrors and glass it carries no noise (or, in table
  /// mode, only the small lights' direct light), so more light paths per pass buy the same error
  /// sooner (docs/light-tracing.md, "Light paths per pass").
  int pathsPerPixel(const Camera& camera) const;
  void splatParticles(const Camera& camera, uint64_t seed, uint64_t jitterSeed, SamplerMode mode, uint64_t pass,
                      uint64_t begin, uint64_t end, std::vector<Splat>& out, uint64_t& rays) const override;

  /// The light subpaths' walk: IntegratorOptions::maxDepth and rrDepth, and with the luminaires the boxes that end
  /// their lights' particles.
  LightPathOptions pathOptions() const;

  /// pathsPerPixel() of the automatic setting in scenes without mirrors or glass: the error at a
  /// given time stops falling near it on the fixture room (docs/light-tracing.md).
  static constexpr int kAutoPathsPerPixel = 8;
  /// The most light paths per pass the automatic setting takes (2^21: as many as one path per pixel
  /// of a 1920×1080 image): its splats, ≈ 16 bytes per vertex that reaches the camera, stay near
  /// 100 MB.
  static constexpr uint64_t kAutoPathsPerPass = uint64_t(1) << 21;
  /// Memory a pass holds per light path until it sums the splats, bytes: about 4 vertices of a path
  /// reach the camera (the check of an explicit --light-paths against the machine's memory).
  static constexpr double kSplatBytesPerPath = 4.0 * sizeof(Splat);
  /// The sampler of particle @p particle of pass @p pass (of @p n per pass) in stream @p stream:
  /// independent mode Sampler(seed, particle, pass, stream); Sobol' mode one sequence over the whole
  /// run, index g = pass·n + particle (its low 32 bits; the bits above key the scramble), so that a
  /// pass's n particles are consecutive points of the sequence — stratified against each other in
  /// every pair of dimensions, and still a function of (seed, particle, pass) only (any split).
  static Sampler particleSampler(SamplerMode mode, uint64_t seed, uint64_t particle, uint64_t pass, uint64_t n,
                                 uint64_t stream);
  /// The stream index of the particles' samplers (particleSampler).
  static constexpr uint64_t kParticleStream = 0x4c54;  // "LT"
  /// The stream of table mode's delta-first particles of the small area lights.
  static constexpr uint64_t kDeltaFirstStream = 0x4c44;  // "LD"

 private:
  /// Splats vertices @p first, … of @p path (those that reach the pinhole), scaled by @p invN.
  void splatPath(const std::vector<LightVertex>& path, size_t first, const Camera& camera, float invN,
                 std::vector<Splat>& out, uint64_t& rays) const;
  /// Whether a camera ray whose first hit is @p hit (with BSDF @p bsdf there) takes the path
  /// tracer's estimate (a delta surface, a polished patch), so that no particle splats through it.
  bool pathTraced(const Hit& hit, const BSDF& bsdf) const;
  /// Table mode, first hit @p x (not pathTraced) of @p ray: the small lights' own part of the pixel.
  Color smallLightsAt(const Ray& ray, const Hit& x, Sampler& sampler, uint64_t& rays) const;

  /// Σ over the splats of @p path (as splatParticles() makes them) of their grey value², adding the connections'
  /// rays to @p rays.
  double splatMoment(const std::vector<LightVertex>& path, const Camera& camera, uint64_t& rays) const;

  PathWalk fallback_;  ///< for camera rays whose first hit is a delta surface, over lighting_
  bool mirrors_ = false;  ///< the scene has a delta (mirror, glass) material
  bool polished_ = false;  ///< the scene may have polished points (a pbr material below or with a roughness texture)
  bool smallAreaLights_ = false;  ///< table mode: a replaced light has a surface (a BSDF sample can meet it)
  /// Table mode: small area lights and delta surfaces, or small lights and polished surfaces: shoot deltaFirst_ too.
  bool deltaParticles_ = false;
  /// Table mode: the replaced area lights (with polished surfaces every replaced light), for particles whose first
  /// hit is delta (or polished).
  EmissionSampler deltaFirst_;
};

}  // namespace firstshot
