#pragma once
/// @file sky_desc.h
/// The scene's daylight as plain data (the JSON keys "sky" and "environment", docs/scene-format.md): a sky
/// model, resolved to its luminance distribution, or an environment map file. Either lights the scene from infinitely
/// far away; the renderer makes it a large light (render/scene/sky_light.h). The sun is not here: it is a directional
/// LightDesc of the scene (common/formats/json/scene_sky.h).
///
/// Units: the models give luminance in cd/m²; the renderer's radiance is luminance / photometry::kEfficacy on every
/// channel (an achromatic sky, skyRadiance()), the convention of the sensors' lux (docs/photometry.md), so that an
/// upward sensor under an unobstructed sky reads the sky's horizontal illuminance.
#include <string>

#include "common/lights/perez_sky.h"
#include "common/lights/photometry.h"
#include "common/lights/sky_models.h"
#include "common/util/math.h"

namespace firstshot {

/// A sky model of the scene.
struct SkyDesc {
  SkyLuminance dome;                ///< the sky's luminance (cd/m²) over the upper hemisphere
  PerezInput perez;                 ///< Perez skies: the irradiances the dome was made from (for the scene hash)
  double turbidity = 0.0;           ///< Preetham skies: the turbidity of the dome's distribution (0: not one)
  double groundReflectance = 0.2;   ///< ρ of the ground below the horizon
  double sunHorizontalLux = 0.0;    ///< the sun's illuminance on an unobstructed horizontal plane, lux (0: no sun)
  /// Luminance of the ground below the horizon, cd/m²: ρ (E_sky + E_sun) / π (common/lights/sky_models.h).
  double groundLuminance() const { return firstshot::groundLuminance(dome, groundReflectance, sunHorizontalLux); }
};

/// An environment map: a lat-long (equirectangular) image of radiance (render/scene/environment_map.h).
struct EnvironmentDesc {
  std::string file;          ///< resolved path (relative names are taken from the scene file's folder); empty: constant
  float scale = 1.0f;        ///< multiplies every texel
  double rotateDeg = 0.0;    ///< rotation about the up axis (y), degrees
  Color constant{0.0f};      ///< with no file: the same radiance from every direction, W/(m² sr) (before scale)
};

/// The renderer's radiance, W/(m² sr) on each channel, of luminance @p candelaPerM2 (cd/m²): L / kEfficacy.
inline float skyRadiance(double candelaPerM2) { return float(candelaPerM2 / photometry::kEfficacy); }

}  // namespace firstshot
