// Mitsuba 0.6's sky and sun at scale 1, in its RGB renderer's scale (mitsuba_daylight.h).
#include "common/formats/mitsuba/mitsuba_daylight.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "common/color/spectrum_rgb.h"

namespace firstshot::mitsuba {

namespace {

/// The sun's elevations of the table's columns, degrees.
constexpr double kElevations[20] = {0, 1, 2, 3, 4, 6, 8, 10, 13, 16, 20, 25, 30, 35, 40, 50, 60, 70, 80, 90};

// Measured tables, kept as Mitsuba prints them: their rows are data of one shape, not logic.
/// Y_h of Mitsuba 0.6's sky at scale 1 and albedo 0.2; rows: turbidity 1..10, columns: kElevations.
constexpr double kSkyY[10][20] = {
    {0.03379, 0.04552, 0.05632, 0.06556, 0.07368, 0.08748, 0.09887, 0.1085, 0.1207, 0.1308, 0.1419, 0.153, 0.1619,
     0.1689, 0.1746, 0.1833, 0.1897, 0.1955, 0.2013, 0.2087},
    {0.03326, 0.04575, 0.0575, 0.0677, 0.07672, 0.09208, 0.1048, 0.1157, 0.1296, 0.1413, 0.1544, 0.1678, 0.1785,
     0.1869, 0.1934, 0.2024, 0.2093, 0.2164, 0.2245, 0.2335},
    {0.03242, 0.04557, 0.05882, 0.07061, 0.0811, 0.09907, 0.1141, 0.1269, 0.1435, 0.1576, 0.1738, 0.1906, 0.2043,
     0.2152, 0.2237, 0.2351, 0.2424, 0.2491, 0.2569, 0.2663},
    {0.03093, 0.04457, 0.05985, 0.07394, 0.08665, 0.1086, 0.1272, 0.1434, 0.1645, 0.1827, 0.2039, 0.2261, 0.2444,
     0.2591, 0.2708, 0.2867, 0.2959, 0.3021, 0.3073, 0.3119},
    {0.0293, 0.04365, 0.06058, 0.07664, 0.09126, 0.1167, 0.1385, 0.1575, 0.1826, 0.2047, 0.2306, 0.2586, 0.2824,
     0.3022, 0.3183, 0.3404, 0.3516, 0.3573, 0.3642, 0.379},
    {0.02828, 0.04279, 0.0606, 0.07783, 0.09365, 0.1213, 0.145, 0.1657, 0.1931, 0.2174, 0.2465, 0.2786, 0.3066,
     0.3307, 0.3507, 0.3789, 0.3928, 0.3967, 0.3992, 0.4099},
    {0.0272, 0.04132, 0.06032, 0.07898, 0.09616, 0.1264, 0.1524, 0.1755, 0.2064, 0.2342, 0.2682, 0.3072, 0.3425,
     0.3737, 0.4004, 0.4384, 0.4567, 0.46, 0.4575, 0.4591},
    {0.02575, 0.03932, 0.05908, 0.07912, 0.09777, 0.1308, 0.1593, 0.1849, 0.2195, 0.2515, 0.292, 0.3412, 0.3887,
     0.433, 0.4723, 0.5298, 0.5563, 0.5573, 0.5424, 0.5128},
    {0.02466, 0.03685, 0.0564, 0.07707, 0.09671, 0.1318, 0.1625, 0.1903, 0.229, 0.266, 0.3151, 0.3778, 0.442, 0.506,
     0.5665, 0.6636, 0.7133, 0.712, 0.6716, 0.6035},
    {0.02355, 0.03373, 0.05062, 0.06978, 0.08894, 0.1251, 0.1583, 0.1894, 0.2342, 0.2782, 0.3374, 0.4143, 0.496,
     0.5822, 0.6707, 0.834, 0.9358, 0.9402, 0.8583, 0.7401},
};

/// A piecewise-linear table: values @p v at wavelengths @p nm, zero outside.
template <size_t N>
double lerp(const double (&nm)[N], const double (&v)[N], double x) {
  if (x < nm[0] || x > nm[N - 1]) return 0.0;
  const size_t i = std::min<size_t>(size_t(std::upper_bound(nm, nm + N, x) - nm), N - 1);
  const double t = (x - nm[i - 1]) / (nm[i] - nm[i - 1]);
  return v[i - 1] + t * (v[i] - v[i - 1]);
}

// Iqbal's coefficients (cm⁻¹) and the extraterrestrial solar radiance (W/(m² sr nm)), over the visible band.
constexpr double kOzoneNm[53] = {355, 445, 450, 455, 460, 465, 470, 475, 480, 485, 490, 495, 500, 505, 510, 515, 520,
                                 525, 530, 535, 540, 545, 550, 555, 560, 565, 570, 575, 580, 585, 590, 595, 600, 605,
                                 610, 620, 630, 640, 650, 660, 670, 680, 690, 700, 710, 720, 730, 740, 750, 760, 770,
                                 780, 790};
constexpr double kOzone[53] = {0, .003, .003, .004, .006, .008, .009, .012, .014, .017, .021, .025, .03, .035,
                               .04, .045, .048, .057, .063, .07, .075, .08, .085, .095, .103, .11, .12, .122,
                               .12, .118, .115, .12, .125, .13, .12, .105, .09, .079, .067, .057, .048, .036,
                               .028, .023, .018, .014, .011, .01, .009, .007, .004, 0, 0};
constexpr double kGasNm[4] = {759, 760, 770, 771}, kGas[4] = {0, 3.0, 0.21, 0};
constexpr double kWaterNm[13] = {689, 690, 700, 710, 720, 730, 740, 750, 760, 770, 780, 790, 800};
constexpr double kWater[13] = {0, 0.016, 0.024, 0.0125, 1.0, 0.87, 0.061, 0.001, 1e-5, 1e-5, 6e-4, 0.0175, 0.036};
constexpr double kSolarNm[38] = {380, 390, 400, 410, 420, 430, 440, 450, 460, 470, 480, 490, 500,
                                 510, 520, 530, 540, 550, 560, 570, 580, 590, 600, 610, 620, 630,
                                 640, 650, 660, 670, 680, 690, 700, 710, 720, 730, 740, 750};
constexpr double kSolar[38] = {16559.0, 16233.7, 21127.5, 25888.2, 25829.1, 24232.3, 26760.5, 29658.3,
                               30545.4, 30057.5, 30663.7, 28830.4, 28712.1, 27825.0, 27100.6, 27233.6,
                               26361.3, 25503.8, 25060.2, 25311.6, 25355.9, 25134.2, 24631.5, 24173.2,
                               23685.3, 23212.1, 22827.7, 22339.8, 21970.2, 21526.7, 21097.9, 20728.3,
                               20240.4, 19870.8, 19427.2, 19072.4, 18628.9, 18259.2};

}  // namespace

double skyHorizontalLuminance(double turbidity, double elevationDeg) {
  const double t = std::clamp(turbidity, 1.0, 10.0) - 1.0, e = std::clamp(elevationDeg, 0.0, 90.0);
  const int i = std::min(int(t), 8);
  const int j = std::clamp(int(std::upper_bound(std::begin(kElevations), std::end(kElevations), e) -
                               std::begin(kElevations)) - 1, 0, 18);
  const double ft = t - i, fe = (e - kElevations[j]) / (kElevations[j + 1] - kElevations[j]);
  auto row = [&](int k) { return kSkyY[k][j] + fe * (kSkyY[k][j + 1] - kSkyY[k][j]); };
  return row(i) + ft * (row(i + 1) - row(i));
}

Color sunRadiance(double turbidity, double zenithRad) {
  const double beta = 0.04608365822050 * turbidity - 0.04586025928522;
  const double zDeg = zenithRad * 180.0 / kPi, m = 1.0 / (std::cos(zenithRad) + 0.15 * std::pow(93.885 - zDeg, -1.253));
  SampledSpectrum s;  // every 5 nm from 350 to 800 nm, linear between (as the model is tabulated)
  for (int nm = 350; nm <= 800; nm += 5) {
    const double um = nm / 1000.0, ko = lerp(kOzoneNm, kOzone, nm), kg = lerp(kGasNm, kGas, nm);
    const double kwa = lerp(kWaterNm, kWater, nm), w = 2.0;
    const double rayleigh = std::exp(-m * 0.008735 * std::pow(um, -4.08));
    const double aerosol = std::exp(-m * beta * std::pow(um, -1.3));
    const double ozone = std::exp(-m * ko * 0.35);
    const double gas = std::exp(-1.41 * kg * m / std::pow(1.0 + 118.93 * kg * m, 0.45));
    const double water = std::exp(-0.2385 * kwa * w * m / std::pow(1.0 + 20.07 * kwa * w * m, 0.45));
    s.nm.push_back(nm);
    s.value.push_back(lerp(kSolarNm, kSolar, nm) * rayleigh * aerosol * ozone * gas * water);
  }
  return emissionRgb([&](double nm) { return s.at(nm); });
}

double sunSolidAngle() { return 2.0 * kPi * (1.0 - std::cos(0.5358 * 0.5 * kPi / 180.0)); }

}  // namespace firstshot::mitsuba
