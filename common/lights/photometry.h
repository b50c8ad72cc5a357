#pragma once
/// @file photometry.h
/// Radiometric RGB → photometric units (docs/photometry.md). The renderer's RGB channels are linear
/// Rec. 709 / sRGB primaries in watts; luminance weights are those of Rec. 709, and the luminous
/// efficacy is Radiance's 179 lm/W (white light of equal energy over the visible band), so that
/// the lux and cd/m² figures agree with Radiance's rtrace/rpict for the same scene.
#include "common/util/math.h"

namespace firstshot::photometry {

/// Luminous efficacy used by default, lm/W (Radiance's WHTEFFICACY; 683 lm/W is the peak at 555 nm).
inline constexpr double kEfficacy = 179.0;

/// Relative luminance weights of linear Rec. 709 primaries (Y row of the sRGB → XYZ matrix, D65).
inline constexpr double kWeightR = 0.2126, kWeightG = 0.7152, kWeightB = 0.0722;

/// Luminance-weighted radiometric value Y of @p c (W/m² for irradiance, W/(m² sr) for radiance).
inline double luminance(const Color& c) { return kWeightR * c.x + kWeightG * c.y + kWeightB * c.z; }

/// Radiometric RGB of a photometric @p amount with RGB weights @p rgb: rgb · amount / K, so lm → W, cd → W/sr and
/// lx → W/m² (a white [1, 1, 1] has luminance 1, so the result's luminance times K is @p amount). The one conversion of
/// the JSON's "lumens" and "candela" keys (with "color" rescaled to luminance 1) and of glTF light intensities.
inline Color toRadiometric(double amount, const Color& rgb, double efficacy = kEfficacy) {
  return rgb * static_cast<float>(amount / efficacy);
}

/// Illuminance in lux (lm/m²) of RGB irradiance @p E (W/m²) at efficacy @p efficacy (lm/W).
inline double lux(const Color& E, double efficacy = kEfficacy) { return efficacy * luminance(E); }

}  // namespace firstshot::photometry
