#pragma once
// The host's time of day (CIGI Celestial Sphere Control) and the sun it puts in the sky: the date
// and time the host sets, held or running on the IG's clock (the ephemeris model), and the sun's
// direction from a place on the Earth at that instant (libnova: VSOP87 solar position, sidereal
// time), turned to the database's grid north.
//
// CIGI 3.3 leaves the time zone to the IG: the hour and minute are read as local time at
// `[host] celestial_utc_offset_h` hours from UTC (0: UTC).

#include <fieldcast/Time.h>
#include <ig_core/Georeference.h>
#include <ig_core/RenderSettings.h>
#include <io_bridge/cigi/Packets.h>

#include <cstdint>
#include <optional>

namespace fieldcast::app {

/// A civil date and time of day.
struct CivilTime {
  int year = 2000, month = 1, day = 1, hour = 0, minute = 0;
};

/// The date and time of a Celestial Sphere Control (local at `utcOffsetH` hours from UTC) as a
/// Julian day (UT); nothing when its date is not one (month 13, 30 February, year 0).
std::optional<double> julianDayOf(const io::cigi::CelestialSphereControl& packet, double utcOffsetH);

/// The same for a civil date and time in UTC; nothing when it is not a date.
std::optional<double> julianDayUtc(const CivilTime& t);

/// The sun seen from `at` at Julian day `jd` (UT): azimuth clockwise from true north and geometric
/// elevation (no refraction), degrees.
core::SunDirection sunSeenFrom(const core::GeodeticOrigin& at, double jd);

/// The angle (degrees, clockwise) from the grid's north to true north at world point `atM` of
/// `georeference` (the meridian convergence of a projected CRS; near 0 on the tangent plane).
/// Nothing when the point cannot be placed.
std::optional<double> trueNorthInGrid(const core::Georeference& georeference, const glm::dvec3& atM);

/// The host's time of day: set by Celestial Sphere Control, held or running. Link thread only.
class CelestialClock {
 public:
  explicit CelestialClock(double utcOffsetH) noexcept : mUtcOffsetH(utcOffsetH) {}

  /// What a packet did.
  enum class Applied : std::uint8_t {
    Set,      ///< the time was set (or the run/hold changed)
    Kept,     ///< the packet's time is the running clock's minute: it runs on undisturbed
    Refused,  ///< date/time valid but not a date: nothing changed
  };
  /// Applies a Celestial Sphere Control received at `now`. With the ephemeris model enabled the
  /// time runs on from the packet's; disabled, it is held there. A host that repeats the current
  /// minute while the clock runs does not pull it back to the minute's start. Date/Time Valid
  /// clear: only the run/hold is taken.
  Applied apply(const io::cigi::CelestialSphereControl& packet, TimePoint now);

  /// The Julian day (UT) at `now`; nothing until a host has set a time.
  std::optional<double> julianDayAt(TimePoint now) const;

 private:
  double mUtcOffsetH;
  std::optional<double> mJulianDay;  // at mSetAt
  TimePoint mSetAt{};
  bool mRunning = false;
};

}  // namespace fieldcast::app
