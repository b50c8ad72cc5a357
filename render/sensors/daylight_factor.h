#pragma once
/// @file daylight_factor.h
/// The daylight factor at sensors (firstshot-render --daylight-factor, docs/photometry.md):
///     DF = E_inside / E_outside · 100 %,
/// E_inside the illuminance at a sensor under the CIE standard overcast sky alone (the sun, the electric lights and
/// emissive surfaces switched off), E_outside the sky's illuminance on an unobstructed horizontal plane facing up.
/// For the CIE overcast sky L(θ) = Lz (1 + 2 cos θ)/3 (common/lights/sky_models.h) the closed form is
///     E_outside = ∫₀^{2π} ∫₀^{π/2} L(θ) cos θ sin θ dθ dφ = 2π Lz (1/2 + 2/9) = 7π/9 · Lz,
/// the dome alone: an upward plane does not see the ground below the horizon, so the ground's reflectance does not
/// enter E_outside (it does light a room through its windows, as ρ E_sky/π below the horizon).
#include <string>
#include <vector>

#include "common/scene/scene_desc.h"
#include "render/sensors/sensors.h"

namespace firstshot {

/// What daylightFactorScene() did to a scene.
struct DaylightFactorSetup {
  double outsideLux = 0;                 ///< E_outside, lux
  std::vector<std::string> switchedOff;  ///< the lights and emissive materials it switched off, by name
};

/// Makes @p scene its daylight-factor scene: the sky alone (every light, the sun included, removed; every material's
/// emission set to 0; the ground below the horizon lit by the sky alone) and returns E_outside.
/// @throws InputError naming the scene file and the key "sky" unless the scene's sky is cie-overcast.
DaylightFactorSetup daylightFactorScene(SceneDesc& scene);

/// DF in percent of illuminance @p lux under a sky of outside illuminance @p outsideLux (> 0).
inline double daylightFactorPercent(double lux, double outsideLux) { return 100.0 * lux / outsideLux; }

/// DF_min, DF_avg, DF_max and the median of a set, in percent.
struct DaylightFactorSummary {
  double min = 0, avg = 0, max = 0, median = 0;
};
/// The summary of @p results (illuminance in lux) under a sky of outside illuminance @p outsideLux; the median of an
/// even count is the mean of the two middle values.
DaylightFactorSummary summarizeDaylightFactor(const std::vector<SensorResult>& results, double outsideLux);

}  // namespace firstshot
