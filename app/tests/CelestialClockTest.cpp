// The host's time of day (CelestialClock.h): CIGI dates read and refused, the sun where almanacs
// put it, grid north against true north, and the clock held or running.
#include "CelestialClock.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

namespace fieldcast::app {
namespace {

namespace cigi = io::cigi;
using namespace std::chrono_literals;

cigi::CelestialSphereControl at(std::uint32_t mmddyyyy, int hour, int minute, bool running = false) {
  cigi::CelestialSphereControl c;
  c.dateMMDDYYYY = mmddyyyy;
  c.hour = static_cast<std::uint8_t>(hour);
  c.minute = static_cast<std::uint8_t>(minute);
  c.dateTimeValid = true;
  c.ephemerisModelEnabled = running;
  return c;
}

TEST(CelestialDate, ReadsMonthDayYearAndRefusesWhatIsNotADate) {
  // 21 June 2024, 12:00 UT is Julian day 2460483.0.
  EXPECT_NEAR(*julianDayOf(at(6212024, 12, 0), 0.0), 2460483.0, 1e-9);
  // Local time an hour east of UTC: 13:00 there is 12:00 UT.
  EXPECT_NEAR(*julianDayOf(at(6212024, 13, 0), 1.0), 2460483.0, 1e-9);
  EXPECT_TRUE(julianDayOf(at(2292024, 0, 0), 0.0));    // 29 February of a leap year
  EXPECT_FALSE(julianDayOf(at(2292023, 0, 0), 0.0));   // ... not of another
  EXPECT_FALSE(julianDayOf(at(13012024, 0, 0), 0.0));  // month 13
  EXPECT_FALSE(julianDayOf(at(4312024, 0, 0), 0.0));   // 31 April
  EXPECT_FALSE(julianDayOf(at(1010000, 0, 0), 0.0));   // year 0
  EXPECT_FALSE(julianDayOf(at(6212024, 24, 0), 0.0));
  EXPECT_FALSE(julianDayOf(at(6212024, 12, 60), 0.0));
}

TEST(SunPosition, IsWhereTheAlmanacPutsIt) {
  // Greenwich at noon of the June solstice: the sun stands 90° − 51.48° + 23.44° high, due south
  // (solar noon falls two minutes later: a little east of south).
  const core::SunDirection greenwich = sunSeenFrom({51.4769, 0.0}, *julianDayUtc({2024, 6, 21, 12, 0}));
  EXPECT_NEAR(greenwich.elevationDeg, 61.96, 0.2);
  EXPECT_NEAR(greenwich.azimuthDeg, 179.2, 1.0);
  // On the equator at the March equinox the sun rises due east at about 06:07 local solar time.
  const core::SunDirection sunrise = sunSeenFrom({0.0, 0.0}, *julianDayUtc({2024, 3, 20, 6, 7}));
  EXPECT_NEAR(sunrise.elevationDeg, 0.0, 0.6);
  EXPECT_NEAR(sunrise.azimuthDeg, 90.0, 0.6);
  // The built-in terrain's place (46° N, 7° E) at 23:00 UT in December: deep night, in the north.
  const core::SunDirection night = sunSeenFrom({46.0, 7.0}, *julianDayUtc({2024, 12, 21, 23, 0}));
  EXPECT_LT(night.elevationDeg, -50.0);
  EXPECT_TRUE(night.azimuthDeg < 60.0 || night.azimuthDeg > 300.0) << night.azimuthDeg;
  // ... and at its local solar noon (12:00 − 28 min for 7° E, − 2 min equation of time): due south,
  // 90° − 46° − 23.44° high.
  const core::SunDirection noon = sunSeenFrom({46.0, 7.0}, *julianDayUtc({2024, 12, 21, 11, 30}));
  EXPECT_NEAR(noon.elevationDeg, 20.56, 0.3);
  EXPECT_NEAR(noon.azimuthDeg, 180.0, 1.0);
}

TEST(SunPosition, TrueNorthInTheGridIsTheMeridianConvergence) {
  // On the tangent plane at its origin the grid is true north.
  const core::Georeference plane = core::Georeference::tangentPlane({46.0, 7.0});
  EXPECT_NEAR(*trueNorthInGrid(plane, {0.0, 0.0, 0.0}), 0.0, 0.01);
  // UTM zone 32 (central meridian 9° E) at 46° N, 7° E: the convergence (λ − λ₀)·sin φ is −1.44°,
  // grid north lies west of true north, so true north is 1.44° clockwise from grid north.
  const core::Georeference utm = core::Georeference::fromCrs("EPSG:32632");
  const glm::dvec3 there = *utm.toWorld({46.0, 7.0, 0.0});
  EXPECT_NEAR(*trueNorthInGrid(utm, there), 1.44, 0.03);
}

TEST(CelestialClock, IsHeldOrRunsAndARepeatedMinuteDoesNotPullItBack) {
  const TimePoint t0{100s};
  CelestialClock clock(0.0);
  EXPECT_FALSE(clock.julianDayAt(t0));  // no time until a host sets one
  const double noon = *julianDayUtc({2024, 6, 21, 12, 0});

  EXPECT_EQ(clock.apply(at(6212024, 12, 0, false), t0), CelestialClock::Applied::Set);
  EXPECT_EQ(*clock.julianDayAt(t0 + 1h), noon);  // held

  EXPECT_EQ(clock.apply(at(6212024, 12, 0, true), t0), CelestialClock::Applied::Set);
  EXPECT_NEAR((*clock.julianDayAt(t0 + 90s) - noon) * 86400.0, 90.0, 1e-3);  // running
  // A host repeating the minute the clock is in leaves it running; one from another minute sets it.
  EXPECT_EQ(clock.apply(at(6212024, 12, 1, true), t0 + 90s), CelestialClock::Applied::Kept);
  EXPECT_NEAR((*clock.julianDayAt(t0 + 100s) - noon) * 86400.0, 100.0, 1e-3);
  EXPECT_EQ(clock.apply(at(6212024, 18, 30, true), t0 + 100s), CelestialClock::Applied::Set);
  EXPECT_NEAR((*clock.julianDayAt(t0 + 110s) - noon) * 86400.0, 6.5 * 3600.0 + 10.0, 1e-3);

  // Date/Time Valid clear: only the run/hold is taken, from where the clock is.
  cigi::CelestialSphereControl hold = at(1012000, 0, 0, false);
  hold.dateTimeValid = false;
  EXPECT_EQ(clock.apply(hold, t0 + 110s), CelestialClock::Applied::Set);
  EXPECT_NEAR((*clock.julianDayAt(t0 + 1h) - noon) * 86400.0, 6.5 * 3600.0 + 10.0, 1e-3);
  // A valid flag over a date that is not one changes nothing.
  EXPECT_EQ(clock.apply(at(2302024, 3, 0, true), t0 + 2h), CelestialClock::Applied::Refused);
  EXPECT_NEAR((*clock.julianDayAt(t0 + 3h) - noon) * 86400.0, 6.5 * 3600.0 + 10.0, 1e-3);
}

}  // namespace
}  // namespace fieldcast::app
