#include "CelestialClock.h"

#include <libnova/julian_day.h>
#include <libnova/ln_types.h>
#include <libnova/solar.h>
#include <libnova/transform.h>

#include <glm/vec3.hpp>

#include <chrono>
#include <cmath>
#include <numbers>

namespace fieldcast::app {
namespace {

bool isLeapYear(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

int daysInMonth(int year, int month) {
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return month == 2 && isLeapYear(year) ? 29 : kDays[month - 1];
}

constexpr double kSecondsPerDay = 86400.0;

}  // namespace

std::optional<double> julianDayUtc(const CivilTime& t) {
  if (t.year < 1 || t.month < 1 || t.month > 12 || t.day < 1 || t.day > daysInMonth(t.year, t.month) || t.hour < 0 ||
      t.hour > 23 || t.minute < 0 || t.minute > 59) {
    return std::nullopt;
  }
  ln_date date{t.year, t.month, t.day, t.hour, t.minute, 0.0};
  return ln_get_julian_day(&date);
}

std::optional<double> julianDayOf(const io::cigi::CelestialSphereControl& packet, double utcOffsetH) {
  // Date: MMDDYYYY as a decimal number (6212024 is 21 June 2024).
  const std::uint32_t d = packet.dateMMDDYYYY;
  const CivilTime local{static_cast<int>(d % 10000), static_cast<int>(d / 1000000), static_cast<int>(d / 10000 % 100),
                        packet.hour, packet.minute};
  const std::optional<double> jd = julianDayUtc(local);
  if (!jd) return std::nullopt;
  return *jd - utcOffsetH / 24.0;
}

core::SunDirection sunSeenFrom(const core::GeodeticOrigin& at, double jd) {
  ln_equ_posn equatorial{};
  ln_get_solar_equ_coords(jd, &equatorial);
  ln_lnlat_posn observer{at.longitudeDeg, at.latitudeDeg};  // east positive
  ln_hrz_posn horizontal{};
  ln_get_hrz_from_equ(&equatorial, &observer, jd, &horizontal);
  // libnova measures azimuth from the south, westward; ours is from the north, eastward (clockwise).
  return core::SunDirection{std::fmod(horizontal.az + 180.0, 360.0), horizontal.alt};
}

std::optional<double> trueNorthInGrid(const core::Georeference& georeference, const glm::dvec3& atM) {
  const std::optional<core::GeodeticPosition> here = georeference.toGeodetic(atM);
  if (!here) return std::nullopt;
  core::GeodeticPosition north = *here;
  north.latitudeDeg += 0.01;  // about 1.1 km: well inside any projection's domain around a database
  const std::optional<glm::dvec3> a = georeference.toWorld(*here);
  const std::optional<glm::dvec3> b = georeference.toWorld(north);
  if (!a || !b) return std::nullopt;
  return std::atan2(b->x - a->x, b->y - a->y) * 180.0 / std::numbers::pi;
}

CelestialClock::Applied CelestialClock::apply(const io::cigi::CelestialSphereControl& packet, TimePoint now) {
  if (!packet.dateTimeValid) {
    // Only the run/hold: the time goes on (or stops) from where it is.
    if (mJulianDay) mJulianDay = julianDayAt(now);
    mSetAt = now;
    mRunning = packet.ephemerisModelEnabled;
    return Applied::Set;
  }
  const std::optional<double> jd = julianDayOf(packet, mUtcOffsetH);
  if (!jd) return Applied::Refused;
  if (mRunning && packet.ephemerisModelEnabled && mJulianDay) {
    // The packet's minute is the running clock's own: let it run (a host repeating the time
    // would otherwise pull the clock back to the start of the minute, over and over).
    const double ahead = (*julianDayAt(now) - *jd) * kSecondsPerDay;
    if (ahead >= 0.0 && ahead < 60.0) return Applied::Kept;
  }
  mJulianDay = jd;
  mSetAt = now;
  mRunning = packet.ephemerisModelEnabled;
  return Applied::Set;
}

std::optional<double> CelestialClock::julianDayAt(TimePoint now) const {
  if (!mJulianDay) return std::nullopt;
  if (!mRunning) return mJulianDay;
  return *mJulianDay + std::chrono::duration<double>(now - mSetAt).count() / kSecondsPerDay;
}

}  // namespace fieldcast::app
