// Spectra → linear sRGB through the CIE 1931 colour-matching functions (spectrum_rgb.h).
#include "common/color/spectrum_rgb.h"

#include <algorithm>
#include <cmath>

#include "common/color/cie_tables.h"

namespace firstshot {

namespace {

/// The tabulated function @p table at @p nm, linear between entries, 0 outside 360–830 nm.
double tabulated(const double (&table)[cie::kCount], double nm) {
  const double p = (nm - cie::kFirstNm) / cie::kStepNm;
  if (p < 0.0 || p > cie::kCount - 1) return 0.0;
  const int i = std::min(int(p), cie::kCount - 2);
  const double t = p - i;
  return table[i] + t * (table[i + 1] - table[i]);
}

constexpr int kFirstNm = 360, kLastNm = 830;  ///< the 1 nm integration grid

}  // namespace

double SampledSpectrum::at(double lambda) const {
  if (nm.empty() || lambda < nm.front() || lambda > nm.back()) return 0.0;
  const size_t i = size_t(std::upper_bound(nm.begin(), nm.end(), lambda) - nm.begin());
  if (i >= nm.size()) return value.back();
  const double t = (lambda - nm[i - 1]) / (nm[i] - nm[i - 1]);
  return value[i - 1] + t * (value[i] - value[i - 1]);
}

Vec3d spectrumXyz(const std::function<double(double)>& s, bool underD65) {
  Vec3d xyz(0.0);
  double norm = 0.0;
  for (int nm = kFirstNm; nm <= kLastNm; ++nm) {
    const double w = underD65 ? tabulated(cie::kD65, nm) : 1.0, v = s(nm) * w;
    xyz += v * Vec3d(tabulated(cie::kX, nm), tabulated(cie::kY, nm), tabulated(cie::kZ, nm));
    norm += w * tabulated(cie::kY, nm);
  }
  return xyz / norm;
}

Vec3d xyzToLinearSrgb(const Vec3d& c) {
  return {3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
          0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
}

Vec3d linearSrgbToXyz(const Vec3d& c) {
  return {0.4124 * c.x + 0.3576 * c.y + 0.1805 * c.z, 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z,
          0.0193 * c.x + 0.1192 * c.y + 0.9505 * c.z};
}

Color reflectanceRgb(const SampledSpectrum& s) {
  // The white point of the tables (D65 through the 1931 observer) lies within 10⁻⁴ of sRGB's; dividing by the
  // white's RGB removes that rounding, so flat spectra are exactly grey.
  static const Vec3d white = xyzToLinearSrgb(spectrumXyz([](double) { return 1.0; }, true));
  const Vec3d rgb = xyzToLinearSrgb(spectrumXyz([&](double nm) { return s.at(nm); }, true)) / white;
  return Color(glm::max(rgb, Vec3d(0.0)));
}

Color emissionRgb(const std::function<double(double)>& radianceNm) {
  return Color(glm::max(xyzToLinearSrgb(spectrumXyz(radianceNm, false)), Vec3d(0.0)));
}

double planckRadiance(double nm, double kelvin) {
  constexpr double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23;  // SI 2019, exact
  const double lambda = nm * 1e-9;
  return 2.0 * h * c * c / (std::pow(lambda, 5.0) * std::expm1(h * c / (lambda * k * kelvin))) * 1e-9;  // per nm
}

double srgbToLinear(double e) { return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4); }

}  // namespace firstshot
