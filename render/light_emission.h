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
#include <cstdint>
#include <vector>

#include "common/math.h"
#include "common/rng.h"
#include "common/scene_desc.h"
#include "render/lights.h"

namespace fs {

/// One particle leaving a light.
struct EmissionSample {
  uint32_t light = 0;     ///< index into LightSet::lights()
  Vec3 p{0.0f};           ///< origin, m
  Vec3 n{0.0f};           ///< area light: unit front normal at p; directional: the travel direction; point, spot: 0
  Vec3 d{0.0f};           ///< unit direction of travel
  float pdfLight = 0;     ///< probability of having chosen the light
  float pdfPos = 1;       ///< area density of p, 1/m² (1 for point and spot lights: a delta position)
  float pdfDir = 0;       ///< solid-angle density of d, 1/sr (1 for directional lights: a delta direction)
  /// Emitted radiance over the position's density: Le/(pdfLight·pdfPos), W/(m² sr)·m² (area lights);
  /// the light vertex's weight when it is connected to the camera. 0 for the delta lights.
  Color radiance{0.0f};
  /// The particle's power: emitted radiance·|cosθ|/(pdfLight·pdfPos·pdfDir), W. The expected sum
  /// over particles of their power is the scene's total emitted power.
  Color power{0.0f};
  bool deltaPosition = false;   ///< point and spot lights
  bool deltaDirection = false;  ///< directional lights
};

class EmissionSampler {
 public:
  EmissionSampler() = default;
  /// @p lights must outlive the sampler; @p scene gives the bounding sphere for directional lights.
  EmissionSampler(const LightSet& lights, const SceneDesc& scene);

  /// Draws a particle with 4 dimensions of @p sampler. @return false if nothing was emitted (no
  /// light with power, or a zero-weight direction): the particle is then lost (counts zero).
  bool sample(Sampler& sampler, EmissionSample& out) const;
  /// The origin part of sample(): a light by power with @p u, a point with @p uPos. Sets light, p,
  /// n, pdfLight, pdfPos, radiance (area lights) and the delta flags, not d, pdfDir or power (the
  /// NEE strategy s = 1 of bidirectional path tracing). @return false if no light has power.
  bool sampleOrigin(double u, const Vec2& uPos, EmissionSample& out) const;

  /// Probability of choosing light @p l (its share of the power).
  float pdfChoice(size_t l) const { return total_ > 0 ? float(power_[l] / total_) : 0.0f; }
  /// Area density of sampleOrigin()'s point on @p light, 1/m² (1 for point and spot: a delta position;
  /// directional: over the disk across the beam).
  float pdfPosition(const RenderLight& light) const;
  /// Solid-angle density with which sample() emits direction @p d from a point of @p light with
  /// front normal @p n (area lights), 1/sr; 0 outside a spot's cone, behind an area light, and for
  /// directional lights (a delta direction).
  float pdfDirection(const RenderLight& light, const Vec3& n, const Vec3& d) const;

  /// Power of light @p l (channel mean), W.
  double power(size_t l) const { return power_[l]; }
  /// Total emitted power (channel mean), W.
  double totalPower() const { return total_; }

 private:
  const LightSet* lights_ = nullptr;
  std::vector<double> power_;  ///< by light
  std::vector<double> cdf_;    ///< by light, last entry 1
  double total_ = 0;
  Vec3 centre_{0.0f};          ///< bounding sphere, m
  float radius_ = 0;
};

}  // namespace fs
