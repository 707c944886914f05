// Georeference: WGS 84 latitude/longitude/altitude ↔ world metres. Known answers come from outside
// this code: a UTM point from GeographicLib's GeoConvert documentation, the meridian arc and the
// parallel's radius from the ellipsoid's formulas (integrated here), not from PROJ.
#include <ig_core/Georeference.h>
#include <ig_core/TerrainDatabase.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace fieldcast::core {
namespace {

using ::testing::HasSubstr;

constexpr double kA = 6378137.0;            // WGS 84 semi-major axis
constexpr double kF = 1.0 / 298.257223563;  // flattening
constexpr double kE2 = kF * (2.0 - kF);     // first eccentricity squared
constexpr double kDeg = std::numbers::pi / 180.0;

// Metres north along a meridian from latitude a to b (degrees): ∫ a(1−e²)/(1−e² sin²φ)^{3/2} dφ.
double meridianArcM(double aDeg, double bDeg) {
  const int n = 2000;
  const double h = (bDeg - aDeg) * kDeg / n;
  double sum = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double phi = aDeg * kDeg + k * h;
    const double s = std::sin(phi);
    const double m = kA * (1.0 - kE2) / std::pow(1.0 - kE2 * s * s, 1.5);
    sum += m * ((k == 0 || k == n) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0));  // Simpson
  }
  return sum * h / 3.0;
}

// Metres between two geodetic positions a few km apart, for the round-trip tolerances.
double groundErrorM(const GeodeticPosition& a, const GeodeticPosition& b) {
  const double north = (a.latitudeDeg - b.latitudeDeg) * kDeg * kA;
  const double east = (a.longitudeDeg - b.longitudeDeg) * kDeg * kA * std::cos(a.latitudeDeg * kDeg);
  return std::hypot(north, east, a.altitudeM - b.altitudeM);
}

TEST(Georeference, AKnownUtmPointLandsOnItsEastingAndNorthing) {
  // GeoConvert(1): "33.3 44.4" → "38n 444140.54 3684706.36".
  const Georeference utm = Georeference::fromCrs("EPSG:32638");
  EXPECT_TRUE(utm.hasCrs());
  EXPECT_THAT(utm.description(), HasSubstr("UTM zone 38N (EPSG:32638)"));
  const std::optional<glm::dvec3> world = utm.toWorld({33.3, 44.4, 120.0});
  ASSERT_TRUE(world);
  EXPECT_NEAR(world->x, 444140.54, 0.01);
  EXPECT_NEAR(world->y, 3684706.36, 0.01);
  EXPECT_EQ(world->z, 120.0);
}

TEST(Georeference, ADatabaseInUtmPlacesThePointRelativeToItsOrigin) {
  DatabaseLayout layout;
  layout.crs = "EPSG:32638";
  layout.geometry.originM = {440000.0, 3680000.0};
  const Georeference geo = Georeference::forDatabase(layout);
  const std::optional<glm::dvec3> world = geo.toWorld({33.3, 44.4, 0.0});
  ASSERT_TRUE(world);
  const glm::dvec2 fromOrigin = glm::dvec2(*world) - layout.geometry.originM;
  EXPECT_NEAR(fromOrigin.x, 4140.54, 0.01);
  EXPECT_NEAR(fromOrigin.y, 4706.36, 0.01);
}

TEST(Georeference, RoundTripsWithinAMillimetre) {
  const GeodeticPosition points[] = {
      {33.3, 44.4, 0.0}, {33.25, 44.31, 1500.0}, {33.41, 44.52, -30.0}, {33.0, 44.0, 8848.0}, {33.7, 44.9, 12.5}};
  for (const char* crs : {"EPSG:32638", "EPSG:3857"}) {
    const Georeference geo = Georeference::fromCrs(crs);
    for (const GeodeticPosition& p : points) {
      const std::optional<glm::dvec3> world = geo.toWorld(p);
      ASSERT_TRUE(world);
      const std::optional<GeodeticPosition> back = geo.toGeodetic(*world);
      ASSERT_TRUE(back);
      EXPECT_LT(groundErrorM(p, *back), 1e-3) << crs << " at " << p.latitudeDeg << ", " << p.longitudeDeg;
    }
  }
  const Georeference plane = Georeference::tangentPlane();
  for (const GeodeticPosition& p :
       {GeodeticPosition{46.0, 7.0, 0.0}, GeodeticPosition{46.12, 7.2, 2500.0}, GeodeticPosition{45.9, 6.85, 3.0}}) {
    const std::optional<GeodeticPosition> back = plane.toGeodetic(*plane.toWorld(p));
    ASSERT_TRUE(back);
    EXPECT_LT(groundErrorM(p, *back), 1e-3) << p.latitudeDeg << ", " << p.longitudeDeg;
  }
}

TEST(Georeference, TheTangentPlaneHasItsOriginAtWorldZeroAndTrueDistances) {
  const Georeference plane = Georeference::tangentPlane();
  EXPECT_FALSE(plane.hasCrs());
  EXPECT_EQ(plane.description(), "local tangent plane at 46.000000 N, 7.000000 E");
  const glm::dvec3 origin =
      *plane.toWorld({kBuiltinTerrainOrigin.latitudeDeg, kBuiltinTerrainOrigin.longitudeDeg, 0.0});
  EXPECT_NEAR(origin.x, 0.0, 1e-6);
  EXPECT_NEAR(origin.y, 0.0, 1e-6);
  // 0.1° north along the origin's meridian: y is the meridian arc, x stays 0.
  const glm::dvec3 north = *plane.toWorld({46.1, 7.0, 0.0});
  EXPECT_NEAR(north.x, 0.0, 1e-6);
  EXPECT_NEAR(north.y, meridianArcM(46.0, 46.1), 1e-3);
  // 0.01° east on the origin's parallel: x is the parallel's radius times the angle (the
  // projection's higher terms are below a micrometre here); up is the altitude as given.
  const double s = std::sin(46.0 * kDeg);
  const double parallelRadius = kA * std::cos(46.0 * kDeg) / std::sqrt(1.0 - kE2 * s * s);
  const glm::dvec3 east = *plane.toWorld({46.0, 7.01, 950.0});
  EXPECT_NEAR(east.x, parallelRadius * 0.01 * kDeg, 1e-3);
  EXPECT_EQ(east.z, 950.0);
  // Another origin moves the plane with it.
  const Georeference elsewhere = Georeference::tangentPlane({-33.86, 151.21});
  EXPECT_EQ(elsewhere.description(), "local tangent plane at 33.860000 S, 151.210000 E");
  EXPECT_NEAR(elsewhere.toWorld({-33.86, 151.21, 0.0})->x, 0.0, 1e-6);
}

TEST(Georeference, ADatabaseWithoutACrsGetsTheTangentPlane) {
  DatabaseLayout layout;  // no CRS, like a version 1 file or the built-in terrain
  const Georeference geo = Georeference::forDatabase(layout);
  EXPECT_FALSE(geo.hasCrs());
  const glm::dvec3 p = *geo.toWorld({46.05, 7.05, 10.0});
  EXPECT_GT(p.x, 3000.0);
  EXPECT_GT(p.y, 5000.0);
}

TEST(Georeference, UnusableInputIsRefusedOrAnswersNothing) {
  EXPECT_THROW(Georeference::fromCrs("not a crs"), GeoreferenceError);
  try {
    Georeference::fromCrs("EPSG:4326");
    FAIL() << "a geographic CRS was accepted for a database's world";
  } catch (const GeoreferenceError& e) {
    EXPECT_THAT(e.what(), HasSubstr("not projected"));
  }
  EXPECT_THROW(Georeference::tangentPlane({91.0, 0.0}), GeoreferenceError);
  const Georeference utm = Georeference::fromCrs("EPSG:32638");
  EXPECT_FALSE(utm.toWorld({std::nan(""), 44.0, 0.0}));
  EXPECT_FALSE(utm.toWorld({95.0, 44.0, 0.0}));
  EXPECT_FALSE(utm.toGeodetic({std::nan(""), 0.0, 0.0}));
}

}  // namespace
}  // namespace fieldcast::core
