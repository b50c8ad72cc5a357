#pragma once
/// @file cie_tables.h
/// Tabulated colorimetric data: the CIE 1931 2° colour-matching functions x̄, ȳ, z̄ and the CIE standard illuminant
/// D65's relative spectral power, from 360 to 830 nm in 5 nm steps (95 values each; common/color/cie_tables.cpp). Between
/// the tabulated wavelengths they are interpolated linearly (common/color/spectrum_rgb.h).

namespace firstshot::cie {

inline constexpr double kFirstNm = 360.0;  ///< wavelength of the first entry, nm
inline constexpr double kStepNm = 5.0;     ///< spacing, nm
inline constexpr int kCount = 95;          ///< entries: 360, 365, …, 830 nm

extern const double kX[kCount];    ///< x̄(λ), dimensionless
extern const double kY[kCount];    ///< ȳ(λ) = V(λ), dimensionless (1 at 555 nm)
extern const double kZ[kCount];    ///< z̄(λ), dimensionless
extern const double kD65[kCount];  ///< D65 relative spectral power, 1 at 560 nm

}  // namespace firstshot::cie
