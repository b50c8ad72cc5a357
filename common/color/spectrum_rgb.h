#pragma once
/// @file spectrum_rgb.h
/// Spectra → the renderer's linear sRGB (Rec. 709 primaries, D65 white), through the CIE 1931 2° colour-matching
/// functions (common/color/cie_tables.h), integrated in 1 nm steps over 360–830 nm with the tables and the spectrum
/// interpolated linearly. Two readings of a spectrum:
/// - a **reflectance** (dimensionless) is seen under D65: XYZ = Σ ρ D65 (x̄, ȳ, z̄) / Σ D65 ȳ, then sRGB, each
///   channel divided by that of ρ = 1, so that a flat spectrum of 1 is exactly (1, 1, 1) and of 0.5 is 0.5 grey;
/// - an **emission** (spectral radiance, W/(m² sr nm)) is taken as it is: XYZ = Σ L (x̄, ȳ, z̄) / Σ ȳ, so that the
///   result's luminance Y is the ȳ-weighted mean of L over the band, W/(m² sr) per channel in the scale that Mitsuba's
///   RGB renderer gives the same spectrum (a flat 1 has Y = 1 and the equal-energy white's colour (1.205, 0.948,
///   0.909)); docs/scene-format.md, "Mitsuba 3 XML scenes", says why this scale and not the photometric one.
#include <functional>
#include <vector>

#include "common/util/math.h"

namespace firstshot {

/// A spectrum sampled at increasing wavelengths (nm), linear between them and zero outside (as Mitsuba's
/// wavelength:value lists).
struct SampledSpectrum {
  std::vector<double> nm;     ///< strictly increasing, nm
  std::vector<double> value;  ///< one per wavelength
  /// The value at @p lambda nm.
  double at(double lambda) const;
};

/// CIE XYZ of the spectrum @p s (a function of the wavelength in nm), weighted by D65 when @p underD65, normalised
/// by Σ (D65) ȳ: Y is the weighted mean of s.
Vec3d spectrumXyz(const std::function<double(double)>& s, bool underD65);

/// Linear sRGB of CIE XYZ (IEC 61966-2-1 matrix).
Vec3d xyzToLinearSrgb(const Vec3d& xyz);
/// CIE XYZ of linear sRGB.
Vec3d linearSrgbToXyz(const Vec3d& rgb);

/// A reflectance spectrum's linear sRGB (see the file comment); negative channels clamped to 0.
Color reflectanceRgb(const SampledSpectrum& s);
/// An emission spectrum's linear sRGB, W/(m² sr) per channel (see the file comment); negative channels clamped to 0.
Color emissionRgb(const std::function<double(double)>& radianceNm);

/// Planck's spectral radiance of a black body at @p kelvin, W/(m² sr nm), at wavelength @p nm.
double planckRadiance(double nm, double kelvin);

/// The sRGB transfer function undone: an 8-bit-style encoded value in [0, 1] → linear (IEC 61966-2-1).
double srgbToLinear(double encoded);

}  // namespace firstshot
