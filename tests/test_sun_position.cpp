// The sun's position (common/lights/sun_position.h) against published worked examples: Meeus, "Astronomical Algorithms"
// (2nd ed.) examples 7.a (Julian Day), 12.a (sidereal time) and 25.a (solar coordinates, with the VSOP87 values
// the example quotes as the truth), and NREL's SPA test case (Reda & Andreas 2004, the topocentric zenith and
// azimuth at Golden, Colorado). The stated accuracy is 0.01° in the sun's direction; invalid dates are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "common/lights/sun_position.h"

using namespace firstshot;

TEST(SunPosition, JulianDayOfMeeusExample7a) {
  // 1957 October 4.81 (Sputnik's launch) = JD 2436116.31; J2000.0 = JD 2451545.0.
  EXPECT_NEAR(julianDay({1957, 10, 4, 19, 26, 24.0, 0.0}), 2436116.31, 1e-6);
  EXPECT_NEAR(julianDay({2000, 1, 1, 12, 0, 0.0, 0.0}), 2451545.0, 1e-9);
  // The same moment written in another zone: 13:00 at UTC+1 is 12:00 UTC.
  EXPECT_NEAR(julianDay({2000, 1, 1, 13, 0, 0.0, 1.0}), 2451545.0, 1e-9);
}

TEST(SunPosition, SiderealTimeOfMeeusExample12a) {
  // 1987 April 10, 0h UT: mean sidereal time 13h10m46.3668s.
  const double expected = (13 + (10 + 46.3668 / 60.0) / 60.0) * 15.0;
  EXPECT_NEAR(greenwichMeanSiderealTimeDeg(julianDay({1987, 4, 10, 0, 0, 0.0, 0.0})), expected, 1e-6);
}

TEST(SunPosition, SolarCoordinatesOfMeeusExample25a) {
  // 1992 October 13.0 TD. The example's own results (the same low-accuracy method) ...
  const SolarCoordinates s = solarCoordinates(2448908.5);
  EXPECT_NEAR(s.apparentLongitudeDeg, 199.90895, 2e-5);
  EXPECT_NEAR(s.obliquityDeg, 23.43999, 2e-5);
  EXPECT_NEAR(s.rightAscensionDeg, 198.38083, 2e-5);
  EXPECT_NEAR(s.declinationDeg, -7.78507, 2e-5);
  EXPECT_NEAR(s.distanceAu, 0.99766, 1e-5);
  // ... and the truth it quotes (VSOP87): the stated 0.01°.
  EXPECT_NEAR(s.rightAscensionDeg, 198.378178, 0.01);
  EXPECT_NEAR(s.declinationDeg, -7.783871, 0.01);
}

TEST(SunPosition, SpaTestCaseAtGoldenColorado) {
  // Reda & Andreas (2004), NREL/TP-560-34302, the example of its appendix: 2003 October 17, 12:30:30 at UTC−7,
  // latitude 39.742476°, longitude −105.1786°, 820 mbar, 11 °C: topocentric zenith 50.11162°, azimuth 194.34024°.
  const SunPosition p = sunPosition({2003, 10, 17, 12, 30, 30.0, -7.0}, 39.742476, -105.1786, {820.0, 11.0});
  EXPECT_NEAR(p.zenithDeg(), 50.11162, 0.01);
  EXPECT_NEAR(p.azimuthDeg, 194.34024, 0.01);
}

TEST(SunPosition, NoonSunStandsSouthAtTheEquinoxAltitude) {
  // Greenwich, 2024 March 20 (equinox 03:06 UTC) near 12:07 UTC (equation of time ≈ −7.5 min): the sun is due
  // south within a degree and its altitude is 90° − latitude within its declination (< 0.5°) plus refraction.
  const SunPosition p = sunPosition({2024, 3, 20, 12, 7, 30.0, 0.0}, 51.4769, 0.0, {0.0, 10.0});
  EXPECT_NEAR(p.azimuthDeg, 180.0, 1.0);
  EXPECT_NEAR(p.altitudeDeg, 90.0 - 51.4769, 0.5);
}

TEST(SunPosition, DirectionInTheSceneFrame) {
  // North = −z, so east = +x: a sun in the east at 30° altitude.
  const Vec3d d = sunDirection({30.0, 90.0}, Vec3d(0, 0, -1));
  EXPECT_NEAR(d.x, std::cos(30.0 * M_PI / 180), 1e-12);
  EXPECT_NEAR(d.y, 0.5, 1e-12);
  EXPECT_NEAR(d.z, 0.0, 1e-12);
  const Vec3d s = sunDirection({0.0, 180.0}, Vec3d(0, 0, -1));  // south on the horizon: +z
  EXPECT_NEAR(s.z, 1.0, 1e-12);
}

TEST(SunPosition, InvalidDatesAreRefusedByField) {
  std::string why;
  EXPECT_TRUE(isValidCivilTime({2024, 2, 29, 12, 0, 0.0, 0.0}));
  EXPECT_FALSE(isValidCivilTime({2023, 2, 29, 12, 0, 0.0, 0.0}, &why));
  EXPECT_NE(why.find("day"), std::string::npos) << why;
  EXPECT_FALSE(isValidCivilTime({1900, 2, 29, 12, 0, 0.0, 0.0}));  // not a leap year
  EXPECT_TRUE(isValidCivilTime({2000, 2, 29, 12, 0, 0.0, 0.0}));    // a leap year
  EXPECT_FALSE(isValidCivilTime({2024, 13, 1, 12, 0, 0.0, 0.0}, &why));
  EXPECT_NE(why.find("month"), std::string::npos) << why;
  EXPECT_FALSE(isValidCivilTime({2024, 4, 31, 12, 0, 0.0, 0.0}));
  EXPECT_FALSE(isValidCivilTime({2024, 4, 1, 24, 0, 0.0, 0.0}));
  EXPECT_FALSE(isValidCivilTime({2024, 4, 1, 12, 60, 0.0, 0.0}));
  EXPECT_FALSE(isValidCivilTime({2024, 4, 1, 12, 0, 60.0, 0.0}));
  EXPECT_FALSE(isValidCivilTime({2024, 4, 1, 12, 0, 0.0, 15.0}));
}
