#pragma once
/// @file ies.h
/// IES LM-63 photometric files (LM-63-1986/1991/1995/2002/2019): the candela table of a luminaire,
/// expanded to its full angular range, with bilinear interpolation, its exact integral (the flux)
/// and a piecewise-constant direction distribution for emission sampling.
///
/// Angles are in the luminaire's LOCAL frame (X, Y, Z), built by common/lights/emission_profile.h:
/// - type C (1): Z = photometric axis (nadir, vertical angle V = 0), X = the C0 half-plane,
///   Y = X × Z (C90). V = acos Z ∈ [0, 180], C = atan2(Y, X) ∈ [0, 360).
/// - type B (2): Z = axis (forward), Y = up, X = Z × Y (right). H = asin X ∈ [−90, 90] (+H right),
///   V = atan2(Y, Z) (+V up): planes through the horizontal X axis.
/// - type A (3): same frame. V = asin Y (+V up), H = atan2(X, Z) (+H right): planes through the
///   vertical Y axis.
/// Outside the file's angular range the intensity is zero.
#include <memory>
#include <string>
#include <vector>

#include "common/sampling/distribution_1d.h"
#include "common/util/math.h"

namespace firstshot {

enum class IesType : int { C = 1, B = 2, A = 3 };

/// A parsed photometric table, candela absolute (× candela multiplier × ballast factor).
struct IesData {
  std::string file;            ///< where it was read from (for messages)
  IesType type = IesType::C;
  double lamps = 1;            ///< number of lamps
  double lumensPerLamp = -1;   ///< rated lumens per lamp; −1: absolute photometry
  std::vector<double> vertical;    ///< V angles, degrees, strictly increasing
  std::vector<double> horizontal;  ///< H angles, degrees, strictly increasing, symmetries expanded
                                   ///< (type C: [0, 360] unless the file covers less)
  std::vector<double> candela;     ///< [h · vertical.size() + v], cd
  double maxCandela = 0;           ///< largest table value, cd
  double flux = 0;                 ///< ∫ I dω over the sphere of the interpolated table, lm (cd·sr)

  /// Bilinear intensity at angles (@p v, @p h) in degrees (h of type C taken modulo 360), cd; 0 outside the table.
  double value(double v, double h) const;
  /// Intensity in the local direction @p d (unit), cd.
  double valueLocal(const Vec3d& d) const;
  /// The (V, H) angles of local direction @p d, degrees.
  void angles(const Vec3d& d, double& v, double& h) const;
  /// A local direction drawn from the piecewise-constant distribution (per table cell: its largest
  /// corner value, uniform in solid angle inside the cell; @p u0 picks the cell and its remainder
  /// one coordinate in it, @p u1 the other); @p pdf receives its density, 1/sr.
  Vec3d sampleLocal(double u0, double u1, double& pdf) const;
  /// Density of sampleLocal at local direction @p d, 1/sr.
  double pdfLocal(const Vec3d& d) const;

  // The sampling distribution (built by parseIes).
  /// Per cell [i · (nh − 1) + j]: its largest corner value × its solid angle, cd·sr (total(): their sum).
  Distribution1D cells;
};

/// Largest .ies file read, bytes.
inline constexpr size_t kMaxIesBytes = size_t(16) << 20;

/// Parses LM-63 text. @p file names the file in messages.
/// @throws InputError naming the file and line for malformed or unsupported content (TILT other than NONE).
IesData parseIes(const std::string& text, const std::string& file);

/// Reads and parses an .ies file. @throws InputError (missing or unreadable file: names @p file).
std::shared_ptr<const IesData> loadIes(const std::string& file);

}  // namespace firstshot
