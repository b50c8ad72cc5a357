#pragma once
/// @file luminaire_split.h
/// Whether the shooting integrators (light tracing, BDPT) split a luminaire's light at its box, and how many of its
/// particles each part gets (docs/luminaires.md, "Split or not: the shooting integrators").
///
/// Split, a luminaire's particles leave either its lights (the inner part: what the camera sees inside the box, and the
/// light that leaves it straight or through glass) or its exit patches (the exit part: the light that leaves after a
/// bounce inside), two independent estimators; unsplit, every particle leaves the lights and carries all three. With A
/// the inner part's and B the exit part's per-particle second moment in the picture, as unsplit particles make them,
/// and f = exitPower/power the share of the lights' power in the exit part, unsplit particles give a variance A + B;
/// split, a share x of them to the lights gives A/x + f·B/(1 − x) (an exit particle carries the exit part alone, every
/// one at the same power), least at x = √A/(√A + √(f·B)), where it is (√A + √(f·B))². The split pays only where that is
/// below A + B: a bowl that sends half its light straight out (A large), or a shade whose inside the camera sees, does
/// not; a fixture that sends little out, and little of it straight, does. A and B are measured on the camera's
/// picture by a short run of unsplit light tracing (kSplitParticles, deterministic).
#include <cstdint>
#include <vector>

#include "render/lights/light_emission.h"
#include "render/scene/render_scene.h"

namespace firstshot {

/// One luminaire's split (EmissionSampler::addExits).
struct LuminaireSplit {
  bool split = false;  ///< its particles split at its box (false: every particle leaves its lights, none its exits)
  /// Split: its lights' choice weight as a share of their power (the exit patches keep theirs): x/(1 − x)·f, so that
  /// x of its particles leave its lights. Unsplit: 1.
  double innerShare = 1.0;
  double inner = 0, exit = 0;  ///< the measured A and B (per particle of the run, picture units²)
};

/// The particles of the measuring run, over all emitters.
inline constexpr uint64_t kSplitParticles = 1u << 15;

/// Measures A and B for every luminaire of @p scene with unsplit light tracing from @p plain (the emitters without
/// exits) seen by @p scene's camera, at most @p maxDepth bounces, and decides each split. Deterministic (fixed
/// numbers, sums in a fixed order). @p rays counts the rays traced.
std::vector<LuminaireSplit> measureLuminaireSplits(const RenderScene& scene, const EmissionSampler& plain, int maxDepth,
                                                   uint64_t& rays);

/// @p plain with @p scene's luminaires' exit patches (EmissionSampler::addExits): each luminaire split where
/// measureLuminaireSplits() finds that it pays, or with @p everyOne all of them (at addExits' default shares).
EmissionSampler emittersWithExits(const RenderScene& scene, const EmissionSampler& plain, int maxDepth, bool everyOne);

}  // namespace firstshot
