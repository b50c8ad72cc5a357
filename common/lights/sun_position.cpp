#include "common/lights/sun_position.h"

#include <algorithm>
#include <cmath>

namespace firstshot {

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// @p x degrees reduced to [0, 360).
double wrap360(double x) {
  const double r = std::fmod(x, 360.0);
  return r < 0 ? r + 360.0 : r;
}

bool isLeapYear(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

int daysInMonth(int year, int month) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return month == 2 && isLeapYear(year) ? 29 : kDays[month - 1];
}

/// Julian centuries since J2000.0.
double centuries(double jd) { return (jd - 2451545.0) / 36525.0; }

/// Longitude of the Moon's ascending node, degrees (Meeus ch. 22).
double moonNodeDeg(double t) { return 125.04452 - 1934.136261 * t; }

}  // namespace

bool isValidCivilTime(const CivilTime& t, std::string* why) {
  auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (t.year < -4000 || t.year > 10000) return fail("year outside -4000..10000");
  if (t.month < 1 || t.month > 12) return fail("month outside 1..12");
  if (t.day < 1 || t.day > daysInMonth(t.year, t.month)) return fail("day does not exist in that month");
  if (t.hour < 0 || t.hour > 23) return fail("hour outside 0..23");
  if (t.minute < 0 || t.minute > 59) return fail("minute outside 0..59");
  if (!(t.second >= 0.0 && t.second < 60.0)) return fail("second outside [0, 60)");
  if (!(std::abs(t.utcOffsetHours) <= 14.0)) return fail("UTC offset outside -14..14 hours");
  return true;
}

double julianDay(const CivilTime& t) {
  int y = t.year, m = t.month;
  if (m <= 2) {
    y -= 1;
    m += 12;
  }
  const int a = static_cast<int>(std::floor(y / 100.0));
  const int b = 2 - a + static_cast<int>(std::floor(a / 4.0));
  const double dayFraction = (t.hour - t.utcOffsetHours + (t.minute + t.second / 60.0) / 60.0) / 24.0;
  return std::floor(365.25 * (y + 4716)) + std::floor(30.6001 * (m + 1)) + t.day + dayFraction + b - 1524.5;
}

SolarCoordinates solarCoordinates(double jd) {
  const double t = centuries(jd);
  const double l0 = wrap360(280.46646 + t * (36000.76983 + t * 0.0003032));  // geometric mean longitude
  const double m = wrap360(357.52911 + t * (35999.05029 - t * 0.0001537));   // mean anomaly
  const double e = 0.016708634 - t * (0.000042037 + t * 0.0000001267);       // orbit's eccentricity
  const double c = (1.914602 - t * (0.004817 + t * 0.000014)) * std::sin(m * kDeg) +
                   (0.019993 - t * 0.000101) * std::sin(2 * m * kDeg) + 0.000289 * std::sin(3 * m * kDeg);
  const double trueLongitude = l0 + c, anomaly = m + c;
  SolarCoordinates s;
  s.distanceAu = 1.000001018 * (1 - e * e) / (1 + e * std::cos(anomaly * kDeg));
  const double omega = moonNodeDeg(t);
  s.apparentLongitudeDeg = wrap360(trueLongitude - 0.00569 - 0.00478 * std::sin(omega * kDeg));
  const double eps0 = 23.0 + (26.0 + (21.448 - t * (46.8150 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0;
  s.obliquityDeg = eps0 + 0.00256 * std::cos(omega * kDeg);
  const double lambda = s.apparentLongitudeDeg * kDeg, eps = s.obliquityDeg * kDeg;
  s.rightAscensionDeg = wrap360(std::atan2(std::cos(eps) * std::sin(lambda), std::cos(lambda)) / kDeg);
  s.declinationDeg = std::asin(std::sin(eps) * std::sin(lambda)) / kDeg;
  // Nutation in longitude, the four largest terms of Meeus ch. 22 (to 0.5″).
  const double sunL = 280.4665 + 36000.7698 * t, moonL = 218.3165 + 481267.8813 * t;
  s.nutationLongitudeDeg = (-17.20 * std::sin(omega * kDeg) - 1.32 * std::sin(2 * sunL * kDeg) -
                            0.23 * std::sin(2 * moonL * kDeg) + 0.21 * std::sin(2 * omega * kDeg)) / 3600.0;
  return s;
}

double greenwichMeanSiderealTimeDeg(double jd) {
  const double t = centuries(jd);
  return wrap360(280.46061837 + 360.98564736629 * (jd - 2451545.0) + t * t * (0.000387933 - t / 38710000.0));
}

SunPosition sunPosition(const CivilTime& t, double latitudeDeg, double longitudeDeg, const Atmosphere& air) {
  const double jd = julianDay(t);
  const SolarCoordinates s = solarCoordinates(jd);
  const double theta = greenwichMeanSiderealTimeDeg(jd) + s.nutationLongitudeDeg * std::cos(s.obliquityDeg * kDeg);
  const double h = (theta + longitudeDeg - s.rightAscensionDeg) * kDeg;  // local hour angle
  const double phi = latitudeDeg * kDeg, delta = s.declinationDeg * kDeg;
  double altitude =
      std::asin(std::clamp(std::sin(phi) * std::sin(delta) + std::cos(phi) * std::cos(delta) * std::cos(h), -1.0, 1.0)) /
      kDeg;
  const double fromSouth = std::atan2(std::sin(h), std::cos(h) * std::sin(phi) - std::tan(delta) * std::cos(phi)) / kDeg;
  altitude -= 8.794 / 3600.0 / s.distanceAu * std::cos(altitude * kDeg);  // parallax
  if (air.pressureMbar > 0 && altitude > -1.0) {
    const double arcmin = 1.02 / std::tan((altitude + 10.3 / (altitude + 5.11)) * kDeg);
    altitude += arcmin / 60.0 * (air.pressureMbar / 1010.0) * (283.0 / (273.0 + air.temperatureC));
  }
  return {altitude, wrap360(fromSouth + 180.0)};
}

Vec3d sunDirection(const SunPosition& sun, const Vec3d& north) {
  const Vec3d up(0, 1, 0), east = glm::cross(north, up);
  const double alt = sun.altitudeDeg * kDeg, az = sun.azimuthDeg * kDeg;
  return std::cos(alt) * (std::cos(az) * north + std::sin(az) * east) + std::sin(alt) * up;
}

}  // namespace firstshot
