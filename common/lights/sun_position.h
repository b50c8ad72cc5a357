#pragma once
/// @file sun_position.h
/// Where the sun stands for a place and a moment (daylight). The solar coordinates are those of
/// Meeus, "Astronomical Algorithms" (2nd ed., 1998), chapter 25 (the sun's apparent longitude to 0.01°, with the
/// main nutation and aberration terms), the sidereal time of chapter 12, the horizontal coordinates of chapter 13,
/// the solar parallax and Saemundsson's refraction formula (Meeus chapter 16, scaled by pressure and temperature).
/// Accuracy: about 0.01° in the sun's direction for the years 1950–2050 (tests/test_sun_position.cpp checks Meeus'
/// worked examples and NREL's SPA test case, Reda & Andreas 2004, within that).
///
/// Conventions: latitude north positive, longitude EAST positive (degrees); time is civil time at a fixed UTC offset
/// in hours (e.g. −7 for MST: no daylight saving rule is applied). Azimuth is measured from north towards east
/// (0° north, 90° east); altitude above the horizon. Universal time is used for terrestrial time (ΔT ≈ 69 s moves
/// the sun by under 0.001°).
#include <string>

#include "common/util/math.h"

namespace firstshot {

/// A civil date and time at a fixed offset from UTC.
struct CivilTime {
  int year = 2000, month = 1, day = 1;  ///< Gregorian calendar
  int hour = 12, minute = 0;
  double second = 0.0;
  double utcOffsetHours = 0.0;  ///< local time minus UTC, hours (e.g. +1 for CET, −7 for MST)
};

/// Whether @p t names a moment that exists: month 1–12, day within its month (leap years of the Gregorian
/// calendar), hour 0–23, minute 0–59, second in [0, 60), offset within ±14 h. @p why, if given, says which field fails.
bool isValidCivilTime(const CivilTime& t, std::string* why = nullptr);

/// Julian Day (days, continuous count from −4712 January 1, 12h) of the UTC moment @p t stands for (Meeus ch. 7).
double julianDay(const CivilTime& t);

/// The sun's geocentric apparent equatorial coordinates, degrees, and its distance in astronomical units.
struct SolarCoordinates {
  double rightAscensionDeg = 0, declinationDeg = 0, distanceAu = 1;
  double apparentLongitudeDeg = 0;  ///< ecliptic longitude with nutation and aberration
  double obliquityDeg = 0;          ///< true obliquity of the ecliptic
  double nutationLongitudeDeg = 0;  ///< Δψ, for the apparent sidereal time
};

/// Meeus ch. 25 (low accuracy, with nutation in longitude from ch. 22's four main terms) at Julian Day @p jd.
SolarCoordinates solarCoordinates(double jd);

/// Greenwich mean sidereal time at Julian Day @p jd (UT), degrees in [0, 360) (Meeus eq. 12.4).
double greenwichMeanSiderealTimeDeg(double jd);

/// The air the sun's light crosses, for the refraction correction.
struct Atmosphere {
  double pressureMbar = 1010.0;   ///< 0 turns refraction off
  double temperatureC = 10.0;
};

/// The sun seen from one place.
struct SunPosition {
  double altitudeDeg = 0;  ///< apparent (topocentric, refracted) altitude above the horizon
  double azimuthDeg = 0;   ///< from north towards east, [0, 360)
  double zenithDeg() const { return 90.0 - altitudeDeg; }
};

/// The apparent sun at @p latitudeDeg, @p longitudeDeg (east positive) and civil time @p t. Refraction by
/// @p air (Saemundsson, applied above −1° altitude); parallax (8.794″/R) included.
SunPosition sunPosition(const CivilTime& t, double latitudeDeg, double longitudeDeg, const Atmosphere& air = {});

/// Unit vector towards the sun in the scene's frame (y up): @p north is the scene's horizontal direction of north
/// (unit, y = 0) and east is north × y (north = −z gives east = +x):
/// cos(altitude)·(cos(azimuth)·north + sin(azimuth)·east) + sin(altitude)·y.
Vec3d sunDirection(const SunPosition& sun, const Vec3d& north);

}  // namespace firstshot
