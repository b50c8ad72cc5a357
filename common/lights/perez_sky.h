#pragma once
/// @file perez_sky.h
/// The Perez all-weather sky, driven by measured irradiances as Radiance's gendaylit is:
/// - Perez, Seals & Michalsky (1993), "All-weather model for sky luminance distribution — preliminary configuration
///   and validation", Solar Energy 50(3) 235–245, with its erratum (Solar Energy 51(5) 423): relative luminance
///   lv(ζ, γ) = [1 + a exp(b / cos ζ)] · [1 + c exp(d γ) + e cos² γ], the five parameters from the sky's clearness ε
///   (8 bins), brightness Δ and the sun's zenith angle Z (the paper's table 1; in the first bin c and d take the
///   paper's exponential forms; Δ ≥ 0.2 for 1.065 < ε < 2.8 per the erratum);
/// - Perez, Ineichen, Seals, Michalsky & Stewart (1990), "Modeling daylight availability and irradiance components
///   from direct and global irradiance", Solar Energy 44(5) 271–289: ε = ((Dh + In)/Dh + κZ³)/(1 + κZ³), κ = 1.041,
///   Δ = Dh·m / (I0·E0) (Kasten's air mass m, I0 = 1367 W/m², Spencer's eccentricity E0), and the luminous efficacies
///   of the diffuse and the direct light (its table 4), with precipitable water W (cm).
/// The dome is scaled so that its horizontal illuminance is Dh × the diffuse efficacy (lux); the sun's direct normal
/// illuminance is In × the direct efficacy. ε is limited to [1, 12) and Δ to [0.01, 0.6], the model's range.
#include "common/lights/sky_models.h"

namespace firstshot {

/// Measured (or typical-year) irradiances for one moment.
struct PerezInput {
  double diffuseHorizontal = 0;  ///< Dh, W/m², > 0
  double directNormal = 0;       ///< In, W/m², ≥ 0
  int dayOfYear = 172;           ///< 1–366, for the extraterrestrial irradiance
  double precipitableWaterCm = 2.0;  ///< W, for the luminous efficacies
};

/// The Perez sky for the sun in direction @p sunDir (unit, y up, above the horizon) and @p in.
struct PerezSky {
  SkyLuminance dome;             ///< the sky's luminance, cd/m² (horizontal illuminance Dh · diffuseEfficacy)
  double clearness = 1;          ///< ε, after limiting
  double brightness = 0;         ///< Δ, after limiting
  double diffuseEfficacy = 0;    ///< lm/W
  double directEfficacy = 0;     ///< lm/W (≥ 0)
  double directNormalLux = 0;    ///< the sun's illuminance on a plane facing it, In · directEfficacy
};

/// Builds the sky. @throws std::invalid_argument for Dh ≤ 0, In < 0, a day outside 1–366 or the sun below the horizon.
PerezSky makePerezSky(const Vec3d& sunDir, const PerezInput& in);

/// The clearness bin (0–7) of ε: bounds 1.065, 1.23, 1.5, 1.95, 2.8, 4.5, 6.2.
int perezClearnessBin(double epsilon);
/// Kasten's relative air mass for the sun's zenith angle @p zenithDeg (< 90°).
double relativeAirMass(double zenithDeg);
/// The diffuse luminous efficacy, lm/W (Perez 1990): a + b W + c cos Z + d ln Δ of ε's bin.
double perezDiffuseEfficacy(double epsilon, double delta, double zenithRad, double waterCm);
/// The direct luminous efficacy, lm/W (Perez 1990): max(0, a + b W + c exp(5.73 Z − 5) + d Δ) of ε's bin.
double perezDirectEfficacy(double epsilon, double delta, double zenithRad, double waterCm);

}  // namespace firstshot
