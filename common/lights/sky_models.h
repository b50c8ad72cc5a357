#pragma once
/// @file sky_models.h
/// Luminance distributions of the daylit sky, in photometric units over the upper hemisphere of the
/// scene's frame (y up). Each model is a relative distribution scaled to a given zenith luminance or a given
/// horizontal illuminance of the sky dome alone (the sun's direct part excluded):
/// - **CIE standard overcast sky** (Moon & Spencer 1942, CIE S 003): L(θ) = Lz (1 + 2 cos θ) / 3, θ the zenith
///   angle, so E_h = ∫ L cos θ dω = 7π/9 · Lz exactly.
/// - **CIE clear sky** (CIE 1973, Kittler's formula, as Radiance's gensky): L(θ, γ) = Lz · φ(θ) f(γ) / (φ(0) f(Z)),
///   φ(θ) = 1 − exp(−0.32 / cos θ), f(γ) = 0.91 + 10 exp(−3γ) + 0.45 cos²γ, γ the angle to the sun, Z the sun's
///   zenith angle; E_h by quadrature (a 512 × 1024 midpoint rule in cos θ and azimuth, error under 10⁻⁴).
/// - **Perez all-weather sky** (common/lights/perez_sky.h): its relative distribution, scaled the same way.
/// - **Preetham clear sky** (Preetham, Shirley & Smits 1999, "A practical analytic model for daylight", appendix A.2):
///   the Perez distribution with parameters linear in the turbidity T, A = 0.1787T − 1.4630, B = −0.3554T + 0.4275,
///   C = −0.0227T + 5.3251, D = 0.1206T − 2.5771, E = −0.0670T + 0.3703 (the paper's Y distribution; T limited to
///   [2, 10], its range), scaled the same way.
/// The ground below the horizon is a Lambertian plane of reflectance ρ lit by sky and sun: L_g = ρ (E_sky + E_sun)/π.
#include <cstdint>

#include "common/util/math.h"

namespace firstshot {

enum class SkyType : uint8_t { CieOvercast, CieClear, Perez };

/// One sky: type, sun direction and scale. A small value type; luminance() is cheap (a few exp/cos).
class SkyLuminance {
 public:
  /// CIE overcast sky whose dome gives @p horizontalLux on an unobstructed horizontal plane.
  static SkyLuminance overcast(double horizontalLux);
  /// CIE clear sky for the sun in direction @p sunDir (unit, y up; the sun may be below the horizon only down to
  /// −0°: the model is not defined for night skies) whose dome gives @p horizontalLux (diffuse horizontal).
  static SkyLuminance clear(const Vec3d& sunDir, double horizontalLux);
  /// Perez all-weather sky with parameters @p abcde (common/lights/perez_sky.h makes them from irradiances) for the sun in
  /// direction @p sunDir, whose dome gives @p horizontalLux. The relative luminance is lv(ζ, γ) / lv(0, Z), clamped
  /// at 0 (a few parameter sets of the model dip below zero near the horizon).
  static SkyLuminance perez(const Vec3d& sunDir, const double (&abcde)[5], double horizontalLux);

  SkyType type() const { return type_; }
  /// Luminance in cd/m² seen looking in direction @p dir (unit); 0 for dir.y ≤ 0 (the ground is separate).
  double luminance(const Vec3d& dir) const;
  /// Luminance at the zenith, cd/m².
  double zenithLuminance() const { return zenith_; }
  /// Horizontal illuminance of the dome, lux: ∫ L cos θ dω over the upper hemisphere.
  double horizontalIlluminance() const { return horizontal_; }
  const Vec3d& sunDirection() const { return sun_; }

  /// Relative luminance L/Lz of the model in direction @p dir (unit, dir.y > 0).
  double relative(const Vec3d& dir) const;

 private:
  SkyType type_ = SkyType::CieOvercast;
  Vec3d sun_{0, 1, 0};
  double zenith_ = 0, horizontal_ = 0;
  double clearNorm_ = 1;  ///< clear sky: 1 / (φ(0) f(Z)); Perez: 1 / lv(0, Z)
  double perez_[5] = {0, 0, 0, 0, 0};  ///< Perez: a, b, c, d, e
};

/// Preetham's Perez parameters a..e of the luminance for turbidity @p turbidity (limited to [2, 10]).
void preethamCoefficients(double turbidity, double (&abcde)[5]);

/// ∫ relative(ω) cos θ dω over the upper hemisphere of @p sky's relative distribution (sr), by the quadrature of the
/// file comment: E_h = Lz times this.
double relativeHorizontalIntegral(const SkyLuminance& sky);

/// Luminance of the ground (cd/m²), a Lambertian plane of reflectance @p rho under the sky dome of @p sky and a sun
/// giving @p sunHorizontalLux on the horizontal: ρ (E_sky + E_sun) / π.
inline double groundLuminance(const SkyLuminance& sky, double rho, double sunHorizontalLux) {
  return rho * (sky.horizontalIlluminance() + sunHorizontalLux) / kPi;
}

}  // namespace firstshot
