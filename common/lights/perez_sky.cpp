#include "common/lights/perez_sky.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace firstshot {

namespace {

/// Perez et al. (1993), table 1: for each clearness bin, the parameters a, b, c, d, e as (x1, x2, x3, x4) with
/// x = x1 + x2 Z + Δ (x3 + x4 Z) (bin 1's c and d: see coefficients()).
constexpr double kLuminance[8][5][4] = {
    {{1.3525, -0.2576, -0.2690, -1.4366}, {-0.7670, 0.0007, 1.2734, -0.1233}, {2.8000, 0.6004, 1.2375, 1.0000},
     {1.8734, 0.6297, 0.9738, 0.2809}, {0.0356, -0.1246, -0.5718, 0.9938}},
    {{-1.2219, -0.7730, 1.4148, 1.1016}, {-0.2054, 0.0367, -3.9128, 0.9156}, {6.9750, 0.1774, 6.4477, -0.1239},
     {-1.5798, -0.5081, -1.7812, 0.1080}, {0.2624, 0.0672, -0.2190, -0.4285}},
    {{-1.1000, -0.2515, 0.8952, 0.0156}, {0.2782, -0.1812, -4.5000, 1.1766}, {24.7219, -13.0812, -37.7000, 34.8438},
     {-5.0000, 1.5218, 3.9229, -2.6204}, {-0.0156, 0.1597, 0.4199, -0.5562}},
    {{-0.5484, -0.6654, -0.2672, 0.7117}, {0.7234, -0.6219, -5.6812, 2.6297}, {33.3389, -18.3000, -62.2500, 52.0781},
     {-3.5000, 0.0016, 1.1477, 0.1062}, {0.4659, -0.3296, -0.0876, -0.0329}},
    {{-0.6000, -0.3566, -2.5000, 2.3250}, {0.2937, 0.0496, -5.6812, 1.8415}, {21.0000, -4.7656, -21.5906, 7.2492},
     {-3.5000, -0.1554, 1.4062, 0.3988}, {0.0032, 0.0766, -0.0656, -0.1294}},
    {{-1.0156, -0.3670, 1.0078, 1.4051}, {0.2875, -0.5328, -3.8500, 3.3750}, {14.0000, -0.9999, -7.1406, 7.5469},
     {-3.4000, -0.1078, -1.0750, 1.5702}, {-0.0672, 0.4016, 0.3017, -0.4844}},
    {{-1.0000, 0.0211, 0.5025, -0.5119}, {-0.3000, 0.1922, 0.7023, -1.6317}, {19.0000, -5.0000, 1.2438, -1.9094},
     {-4.0000, 0.0250, 0.3844, 0.2656}, {1.0468, -0.3788, -2.4517, 1.4656}},
    {{-1.0500, 0.0289, 0.4260, 0.3590}, {-0.3250, 0.1156, 0.7781, 0.0025}, {31.0625, -14.5000, -46.1148, 55.3750},
     {-7.2312, 0.4050, 13.3500, 0.6234}, {1.5000, -0.6426, 1.8564, 0.5636}},
};

/// Perez et al. (1990), table 4: luminous efficacy coefficients (a, b, c, d) per clearness bin.
constexpr double kDiffuseEfficacy[8][4] = {
    {97.24, -0.46, 12.00, -8.91},   {107.22, 1.15, 0.59, -3.95},   {104.97, 2.96, -5.53, -8.77},
    {102.39, 5.59, -13.95, -13.90}, {100.71, 5.94, -22.75, -23.74}, {106.42, 3.83, -36.15, -28.83},
    {141.88, 1.90, -53.24, -14.03}, {152.23, 0.35, -45.27, -7.98}};
constexpr double kDirectEfficacy[8][4] = {
    {57.20, -4.55, -2.98, 117.12}, {98.99, -3.46, -1.21, 12.38}, {109.83, -4.90, -1.71, -8.81},
    {110.34, -5.84, -1.99, -4.56}, {106.36, -3.97, -1.75, -6.16}, {107.19, -1.25, -1.51, -26.73},
    {105.75, 0.77, -1.26, -34.44}, {101.18, 1.58, -1.10, -8.29}};

constexpr double kSolarConstant = 1367.0;  ///< W/m²
constexpr double kKappa = 1.041;

/// Spencer (1971): the extraterrestrial irradiance's factor (R0/R)² for day @p day of the year.
double eccentricity(int day) {
  const double g = 2.0 * kPi * (day - 1) / 365.0;
  return 1.00011 + 0.034221 * std::cos(g) + 0.00128 * std::sin(g) + 0.000719 * std::cos(2 * g) +
         0.000077 * std::sin(2 * g);
}

/// The five parameters a..e for clearness @p eps, brightness @p delta and sun zenith @p z (radians).
void coefficients(double eps, double delta, double z, double (&out)[5]) {
  const int bin = perezClearnessBin(eps);
  const auto& x = kLuminance[bin];
  for (int i = 0; i < 5; ++i) out[i] = x[i][0] + x[i][1] * z + delta * (x[i][2] + x[i][3] * z);
  if (bin == 0) {
    out[2] = std::exp(std::pow(delta * (x[2][0] + x[2][1] * z), x[2][2])) - x[2][3];
    out[3] = -std::exp(delta * (x[3][0] + x[3][1] * z)) + x[3][2] + delta * x[3][3];
  }
}

}  // namespace

int perezClearnessBin(double epsilon) {
  static constexpr double kBounds[7] = {1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200};
  return int(std::upper_bound(std::begin(kBounds), std::end(kBounds), epsilon) - std::begin(kBounds));
}

double relativeAirMass(double zenithDeg) {
  return 1.0 / (std::cos(zenithDeg * kPi / 180.0) + 0.15 * std::pow(93.885 - zenithDeg, -1.253));
}

double perezDiffuseEfficacy(double epsilon, double delta, double zenithRad, double waterCm) {
  const auto& k = kDiffuseEfficacy[perezClearnessBin(epsilon)];
  return k[0] + k[1] * waterCm + k[2] * std::cos(zenithRad) + k[3] * std::log(delta);
}

double perezDirectEfficacy(double epsilon, double delta, double zenithRad, double waterCm) {
  const auto& k = kDirectEfficacy[perezClearnessBin(epsilon)];
  return std::max(0.0, k[0] + k[1] * waterCm + k[2] * std::exp(5.73 * zenithRad - 5.0) + k[3] * delta);
}

PerezSky makePerezSky(const Vec3d& sunDir, const PerezInput& in) {
  if (!(in.diffuseHorizontal > 0)) throw std::invalid_argument("the diffuse horizontal irradiance must be > 0");
  if (!(in.directNormal >= 0)) throw std::invalid_argument("the direct normal irradiance must be >= 0");
  if (in.dayOfYear < 1 || in.dayOfYear > 366) throw std::invalid_argument("the day of the year must be 1..366");
  const Vec3d sun = glm::normalize(sunDir);
  if (!(sun.y > 0)) throw std::invalid_argument("the Perez sky needs the sun above the horizon");
  const double z = std::acos(std::min(sun.y, 1.0)), z3 = kKappa * z * z * z;
  PerezSky p;
  p.clearness = std::clamp(((in.diffuseHorizontal + in.directNormal) / in.diffuseHorizontal + z3) / (1.0 + z3), 1.0,
                           12.0 - 1e-9);
  p.brightness = std::clamp(in.diffuseHorizontal * relativeAirMass(z * 180.0 / kPi) /
                                (kSolarConstant * eccentricity(in.dayOfYear)),
                            0.01, 0.6);
  p.diffuseEfficacy = perezDiffuseEfficacy(p.clearness, p.brightness, z, in.precipitableWaterCm);
  p.directEfficacy = perezDirectEfficacy(p.clearness, p.brightness, z, in.precipitableWaterCm);
  p.directNormalLux = in.directNormal * p.directEfficacy;
  // The erratum: the luminance parameters take Δ ≥ 0.2 in the intermediate bins.
  const double delta = p.clearness > 1.065 && p.clearness < 2.8 ? std::max(p.brightness, 0.2) : p.brightness;
  double abcde[5];
  coefficients(p.clearness, delta, z, abcde);
  p.dome = SkyLuminance::perez(sun, abcde, in.diffuseHorizontal * p.diffuseEfficacy);
  return p;
}

}  // namespace firstshot
