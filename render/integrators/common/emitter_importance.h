#pragma once
/// @file emitter_importance.h
/// Which emitters light tracing's particles leave, by what the camera sees of their light (docs/light-tracing.md,
/// "Emitters chosen by the camera").
///
/// Particles chosen by power spend themselves on lights the camera does not see the light of: a floor of offices seen
/// from one desk, a lamp whose shade keeps most of its power. With emitter groups g (a light, a luminaire's lights and
/// exit patches together, the lit patch sides of a table together) chosen with probabilities q_g, a pass's picture
/// has the variance Σ_g S_g/q_g − const per particle, S_g = q_g·m_g with m_g the second moment of a particle's splats
/// when g's particles are drawn at q_g (each carries its light over q_g); counted per ray, each particle of g costing
/// c_g rays, it is least at q_g ∝ √(S_g/c_g). A short run of light tracing at the power choice (importanceParticles(),
/// fixed numbers, sums in a fixed order: the same for any thread count) measures m_g and c_g, and the choice becomes
/// the mixture (1 − kDefensiveShare)·√(S_g/c_g)/Σ + kDefensiveShare·q_g, so that a group the run saw little of keeps
/// three tenths of its particles (its variance at most 3.3× its share of it at the power choice) and no group gets none.
/// Within a group the emitters keep their relative weights (a luminaire's split, docs/luminaires.md).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "render/integrators/common/light_path.h"
#include "render/lights/light_emission.h"
#include "render/scene/camera.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// The particles of the measuring run: at least kImportanceParticles, kImportanceParticlesPerGroup per emitter group
/// where there are more groups, at most kMaxImportanceParticles (the office floor's 217 lights: 222,208; with 65,536 a
/// light there was measured by ~300 particles: light tracing's noise at 20 s 0.1233 against 0.1134, with a tenth kept
/// by power; docs/light-tracing.md).
inline constexpr uint64_t kImportanceParticles = 1u << 16;
inline constexpr uint64_t kImportanceParticlesPerGroup = 1024;
inline constexpr uint64_t kMaxImportanceParticles = 1u << 18;
/// The share of each group's power choice kept in the mixture (defensive importance sampling).
inline constexpr double kDefensiveShare = 0.3;

/// What one traced light path adds to the camera's picture: Σ over its splats of the splat's value² (grey), the rays
/// its camera connections traced added to @p rays.
using PathSplatMoment = std::function<double(const std::vector<LightVertex>& path, uint64_t& rays)>;

/// One emitter group's measurement.
struct EmitterGroupMoment {
  double choice = 0;     ///< q_g at the power choice
  double particles = 0;  ///< of the run that left it
  double moment = 0;     ///< S_g = q_g·m_g (picture units² per particle)
  double rays = 0;       ///< c_g: rays per particle (walk and camera connections)
  double newChoice = 0;  ///< the mixture's q_g
};

/// The measurement and the factors: per emitter of @p emission (EmissionSampler::emitterCount), the factor its choice
/// weight is multiplied by (EmissionSampler::reweight); empty where nothing was seen (keep the power choice).
struct EmitterImportance {
  std::vector<double> factor;
  std::vector<EmitterGroupMoment> groups;
  /// The run's projected variance × rays per particle, power choice over the new one (≥ 1 but for its noise).
  double gain = 1;
};

/// The measuring run's particles for @p groups emitter groups (a multiple of 1024, as its bounds and step are).
inline uint64_t importanceParticles(size_t groups) {
  return std::clamp<uint64_t>(kImportanceParticlesPerGroup * groups, kImportanceParticles, kMaxImportanceParticles);
}

/// A PathSplatMoment's sum for @p path: Σ over its vertices from @p first on, but those @p skip names, of the grey
/// value² of their connection to @p camera's pinhole (connectToCamera, @p panes as it takes them).
double cameraSplatMoment(const RenderScene& scene, const std::vector<LightVertex>& path, size_t first,
                         const Camera& camera, bool panes, uint64_t& rays,
                         const std::function<bool(size_t)>& skip = nullptr);

/// Measures @p emission's groups (a luminaire's when @p luminaires) with particles traced by @p walk and scored by
/// @p splat, and returns the factors. @p rays counts the run's rays.
EmitterImportance measureEmitterImportance(const RenderScene& scene, const EmissionSampler& emission,
                                           const LightPathOptions& walk, bool luminaires, const PathSplatMoment& splat,
                                           uint64_t& rays);

}  // namespace firstshot
