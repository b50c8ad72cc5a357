#pragma once
/// @file light_emission.h
/// Emission sampling: particles leaving the lights of a LightSet, for shooting (light tracing,
/// and the light subpaths of bidirectional methods). A light is chosen with probability
/// proportional to its power (channel mean), then a point and a direction:
///   - point:       isotropic direction, Φ = 4π·I;
///   - spot:        direction uniform in the outer cone, weighted by the profile, Φ = I0·∫profile;
///   - directional: a point uniform on a disk of the scene's bounding-sphere radius R, placed
///                  R before the sphere's centre and facing the light's direction, Φ = E⊥·πR²;
///   - area:        a point uniform by area, a cosine-distributed direction on the front side, Φ = Le·A·π.
/// Replaced (first-shot) lights are emitted like the others: shooting does not use the table.
///
/// Table mode (the second constructor): the lights a first-shot table replaces leave, and every
/// lit patch side joins as an emitter (render/firstshot/patch_emitters.h): a point uniform on the patch, a
/// cosine-distributed direction into the side's half-space, the first-shot radiance it sends there
/// (Φ ≈ albedo·E·A for the choice). A glossy side (a BSDF that is not Lambertian) sends a lobe about
/// the mirror direction of its lights, which the cosine rarely meets: its direction is drawn from
/// an even mixture of the cosine and the BSDF's own sampling towards the side's light centre (the
/// sample positions' mean weighted by e_i·r_ij). Emitters are numbered lights first (LightSet
/// indices), then the patch sides.
///
/// Luminaires (addExits(), light tracing): the exit patches of a first-shot table's luminaires join as emitters after
/// the patch sides, chosen by their power like the others; a point uniform on the patch, a bin of the exit
/// distribution and a direction inside it (render/lights/exit_emission.h). The luminaires' lights keep emitting.
#include <cstdint>
#include <vector>

#include "common/sampling/distribution_1d.h"
#include "common/sampling/rng.h"
#include "common/scene/scene_desc.h"
#include "common/util/math.h"
#include "render/lights/exit_emission.h"
#include "render/scene/light_set.h"

namespace firstshot {

class FirstShotLighting;
class RenderScene;

/// One particle leaving a light.
struct EmissionSample {
  uint32_t light = 0;     ///< emitter index: a LightSet light (< EmissionSampler::lightCount()), a patch side or an exit patch
  Vec3 p{0.0f};           ///< origin, m
  Vec3 n{0.0f};           ///< area light, patch, exit patch: unit normal of the emitting side at p; directional: the travel direction; point, spot: 0
  Vec3 d{0.0f};           ///< unit direction of travel
  float pdfLight = 0;     ///< probability of having chosen the light
  float pdfPos = 1;       ///< area density of p, 1/m² (1 for point and spot lights: a delta position)
  float pdfDir = 0;       ///< solid-angle density of d, 1/sr (1 for directional lights: a delta direction)
  /// Emitted radiance over the position's density: Le/(pdfLight·pdfPos), W/(m² sr)·m² (area lights);
  /// the light vertex's weight when it is connected to the camera. 0 for the delta lights, for
  /// patches (whose radiance depends on the direction: EmissionSampler::patchRadiance) and for exit patches.
  Color radiance{0.0f};
  /// The particle's power: emitted radiance·|cosθ|/(pdfLight·pdfPos·pdfDir), W. The expected sum
  /// over particles of their power is the scene's total emitted power.
  Color power{0.0f};
  bool deltaPosition = false;   ///< point and spot lights
  bool deltaDirection = false;  ///< directional lights
};

/// Which lights of a LightSet an EmissionSampler emits from.
enum class EmitterSet {
  All,                 ///< every light
  Kept,                ///< the lights a first-shot table does not replace (table mode)
  ReplacedAreaLights,  ///< only the replaced area lights (light tracing's delta-first particles)
  Replaced,            ///< every replaced light (light tracing's first-hit particles in scenes with polished surfaces)
};

class EmissionSampler {
 public:
  EmissionSampler() = default;
  /// @p lights must outlive the sampler; @p scene gives the bounding sphere for directional lights.
  /// @p set: the lights that emit (the others keep their index with no power).
  EmissionSampler(const LightSet& lights, const SceneDesc& scene, EmitterSet set = EmitterSet::All);
  /// Table mode: the lights of @p scene that its first-shot table does not replace, and the lit
  /// patch sides, with radiance from @p lighting (built for @p scene). Both must outlive the sampler.
  EmissionSampler(const RenderScene& scene, const FirstShotLighting& lighting);

  /// Draws a particle with 5 dimensions of @p sampler. The emitter is chosen by inverting the
  /// power CDF at u = (@p stratum + ξ)/@p strata, ξ the first dimension: particles that take
  /// strata 0..n−1 of one pass choose their emitters stratified (and in emitter order, which keeps
  /// their memory accesses close); the default is an independent choice. @return false if nothing
  /// was emitted (no light with power, or a zero-weight direction): the particle then counts zero.
  bool sample(Sampler& sampler, EmissionSample& out, uint64_t stratum = 0, uint64_t strata = 1) const;
  /// The origin part of sample(): a light by power with @p u, a point with @p uPos. Sets light, p,
  /// n, pdfLight, pdfPos, radiance (area lights) and the delta flags, not d, pdfDir or power (the
  /// NEE strategy s = 1 of bidirectional path tracing). @return false if no light has power.
  bool sampleOrigin(double u, const Vec2& uPos, EmissionSample& out) const;
  /// sampleOrigin() from one stratified pair (Sampler::next2Dd): the light by @p uPair.x, its point
  /// by (the remainder of uPair.x inside the light's CDF interval, uPair.y), as the path tracer's
  /// next-event estimation; x's 53 bits keep the choice exact for emitters of tiny power share.
  bool sampleOrigin(const Vec2d& uPair, EmissionSample& out) const;

  /// Adds the exit patches of @p boxes (which must outlive the sampler) as emitters numbered from exitBegin() on, with
  /// the power of their exit distributions, for the luminaires it splits (splits()): @p innerShares, per luminaire,
  /// its lights' choice weight as a share of their power (render/integrators/common/luminaire_split.h), or 0 where it
  /// is not split (its exit patches then have no power, its lights all theirs). Empty: every luminaire split, its
  /// lights chosen by the share of their power that the exit distribution does not hold (1 − exitPower/power, at least
  /// kMinInnerShare). A split luminaire's lights' particles light the inside of its box and the room straight from
  /// the light: power() is their share of their power, and their particles' power grows to match. Nothing if @p boxes
  /// is empty.
  void addExits(const LuminaireBoxes& boxes, const std::vector<double>& innerShares = {});
  /// Whether addExits() split luminaire @p luminaire's light at its box (its lights' particles end where they leave
  /// it after a bounce inside, its exit patches emit the rest).
  bool splits(int luminaire) const {
    return luminaire >= 0 && size_t(luminaire) < split_.size() && split_[size_t(luminaire)];
  }
  /// The least share of a luminaire's light's power its choice keeps (addExits): a clear glass bulb sends almost all
  /// of it out, and the camera still sees the inside.
  static constexpr double kMinInnerShare = 0.05;

  /// Multiplies emitter @p e's choice weight by @p factor[e] (> 0 keeps it unbiased: a particle's power is over its
  /// choice's probability), one per emitter (emitterCount()).
  void reweight(const std::vector<double>& factor);
  /// Number of emitters: lights, patch sides, exit patches.
  size_t emitterCount() const { return power_.size(); }
  /// Probability of choosing emitter @p e (its share of the power).
  float pdfChoice(size_t e) const { return choice_.total() > 0 ? float(power_[e] / choice_.total()) : 0.0f; }
  /// Area density of sampleOrigin()'s point on emitter @p e, 1/m² (1 for point and spot: a delta
  /// position; directional: over the disk across the beam; area light, patch: 1/area).
  float pdfPosition(uint32_t e) const;
  /// Solid-angle density with which sample() emits direction @p d from the point @p y of emitter @p e
  /// with front normal @p n (area lights; a patch side knows its own), 1/sr; 0 outside a spot's cone,
  /// behind an area light or a diffuse patch side, and for directional lights (a delta direction).
  float pdfDirection(uint32_t e, const Vec3& y, const Vec3& n, const Vec3& d) const;

  /// Number of LightSet lights; emitters from this index on are patch sides.
  uint32_t lightCount() const { return lightCount_; }
  bool isPatch(uint32_t e) const { return e >= lightCount_ && e - lightCount_ < patchSides_.size(); }
  /// Whether emitter @p e is an exit patch (addExits()); its number there is e − exitBegin().
  bool isExit(uint32_t e) const { return e >= exitBegin_ && e - exitBegin_ < exits_.count(); }
  /// The emitter number of the first exit patch.
  uint32_t exitBegin() const { return exitBegin_; }
  /// The exit patches' emission (empty without addExits()).
  const ExitEmission& exits() const { return exits_; }
  /// Probability of choosing one of luminaire @p luminaire's exit patches (their pdfChoice() together).
  float luminaireChoice(uint32_t luminaire) const {
    return choice_.total() > 0 ? float(luminairePower_[luminaire] / choice_.total()) : 0.0f;
  }
  /// Exit patch emitter @p e: the radiance it sends in the unit direction @p d (its bin's; 0 into the box), W/(m² sr).
  Color exitRadiance(uint32_t e, const Vec3& d) const { return exits_.radiance(e - exitBegin_, d); }
  /// Number of patch-side emitters (table mode), after the lightCount() lights.
  uint32_t patchSideCount() const { return uint32_t(patchSides_.size()); }
  bool isDirectional(uint32_t e) const;
  /// Table mode: the emitter of side @p side (0: the side the normal faces) of patch @p j, or kNoId.
  uint32_t patchEmitter(uint32_t j, uint32_t side) const;
  /// Patch emitter @p e: the first-shot radiance its point @p y sends in the unit direction @p w,
  /// W/(m² sr); 0 into the other side's half-space.
  Color patchRadiance(uint32_t e, const Vec3& y, const Vec3& w) const;
  /// What the radiance that the point @p y sampled on patch emitter @p e sends in the unit direction
  /// @p w is multiplied by: its cut-out coverage, 0 where another surface lies on y as seen from w
  /// (sampledPatchPointWeight; traces one ray).
  float coverage(uint32_t e, const Vec3& y, const Vec3& w) const;
  /// The patch of patch emitter @p e and its emitting side's unit normal.
  uint32_t patchOf(uint32_t e) const { return patchSides_[e - lightCount_] / 2; }
  Vec3 patchNormal(uint32_t e) const;

  /// Power of emitter @p e (channel mean), W: what it is chosen by (addExits: a luminaire's light's inner share).
  double power(size_t e) const { return power_[e]; }
  /// Total emitted power (channel mean), W.
  double totalPower() const { return choice_.total(); }

 private:
  void setBounds(const SceneDesc& scene);
  void addLights(EmitterSet set);
  void finish();  ///< choice_ from power_
  bool originOf(size_t l, const Vec2& uPos, EmissionSample& out) const;  ///< sampleOrigin()'s point part
  /// A glossy patch side @p e's direction from its point @p y (the mixture above), with its density.
  bool sampleGlossyPatch(uint32_t e, const Vec3& y, Vec2 u, Vec3& d, float& pdf) const;
  /// The mixture's density of @p d at the point @p y of glossy patch side @p e, 1/sr.
  float pdfGlossyPatch(uint32_t e, const Vec3& y, const Vec3& d) const;

  const LightSet* lights_ = nullptr;
  const RenderScene* scene_ = nullptr;            ///< table mode
  const FirstShotLighting* lighting_ = nullptr;   ///< table mode
  uint32_t lightCount_ = 0;
  std::vector<uint32_t> patchSides_;    ///< by patch emitter: 2j + side
  std::vector<uint32_t> sideEmitter_;   ///< table mode, by 2j + side: its emitter index or kNoId
  /// By patch emitter: the light centre of a glossy side (m), NaN for a diffuse one or one without a centre.
  std::vector<Vec3> glossyCentre_;
  std::vector<double> power_;  ///< by emitter
  Distribution1D choice_;      ///< the emitters by power_ (finish())
  ExitEmission exits_;         ///< addExits()
  std::vector<double> luminairePower_;  ///< addExits(): per luminaire, its exit patches' choice weight (Σ power_)
  std::vector<bool> split_;             ///< addExits(): per luminaire, whether it is split
  uint32_t exitBegin_ = 0;     ///< the first exit patch's emitter number
  Vec3 centre_{0.0f};          ///< bounding sphere, m
  float radius_ = 0;
};

}  // namespace firstshot
