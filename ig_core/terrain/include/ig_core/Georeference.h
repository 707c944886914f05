#pragma once
// Where a database lies on the Earth: geodetic WGS-84 latitude, longitude and altitude ↔ the
// database's world metres (x east, y north, z up; types' Conventions.h). The CIGI host link places
// entities and answers HAT/HOT requests through it.
//
// - A database with a CRS (DatabaseLayout::crs): world x, y are coordinates in that CRS (a UTM
//   easting and northing, say, or the local transverse Mercator of a reprojected geographic DEM);
//   latitude and longitude go through PROJ from WGS 84 (EPSG:4326) into it.
// - A database without one (the built-in and synthetic terrain, version 1 files, grids that came
//   without a CRS): a local tangent plane — east-north axes tangent to the WGS 84 ellipsoid at an
//   origin, world (0, 0) at the origin, horizontal positions mapped onto it by a transverse
//   Mercator centred there (scale 1 + x²/2R² at x east of it: 1.1e-5 at 30 km).
//
// Altitude: z is the altitude as given (metres above the datum the terrain's heights use, mean
// sea level for the usual DEM and for CIGI's altitude), not the height above the tangent plane:
// the terrain is a flat grid, so a geometric east-north-up z, which drops by d²/2R (7.8 m at
// 10 km), would sink everything below its own terrain. No geoid or vertical datum transform.
//
// Not thread-safe: one Georeference per thread (each owns its PROJ context).

#include <ig_core/TerrainDatabase.h>

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace fieldcast::core {

/// A CRS PROJ cannot use; what() names it and PROJ's reason.
class GeoreferenceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// WGS 84 geodetic position: degrees north, degrees east, metres (see the altitude note above).
struct GeodeticPosition {
  double latitudeDeg = 0.0;
  double longitudeDeg = 0.0;
  double altitudeM = 0.0;
};

/// Where a tangent plane touches the ellipsoid.
struct GeodeticOrigin {
  double latitudeDeg = 0.0;
  double longitudeDeg = 0.0;
};

/// The built-in terrain's world (0, 0) — the centre of its south-west voxel — lies here: an
/// arbitrary round position (the terrain is synthetic), the default for every database without a CRS.
inline constexpr GeodeticOrigin kBuiltinTerrainOrigin{46.0, 7.0};

class Georeference {
 public:
  /// World x, y in `crs` ("EPSG:n", WKT, a PROJ string). Throws GeoreferenceError.
  static Georeference fromCrs(const std::string& crs);
  /// The local tangent plane at `origin` (world (0, 0) there). Throws GeoreferenceError on an
  /// origin that is not a latitude/longitude.
  static Georeference tangentPlane(GeodeticOrigin origin = kBuiltinTerrainOrigin);
  /// The database's CRS, or the tangent plane at `origin` when it has none.
  static Georeference forDatabase(const DatabaseLayout& layout, GeodeticOrigin origin = kBuiltinTerrainOrigin);
  /// The same for a terrain's CRS text (TileCache::crs(); empty: the tangent plane at `origin`).
  static Georeference forTerrain(const std::string& crs, GeodeticOrigin origin = kBuiltinTerrainOrigin);

  Georeference(Georeference&&) noexcept;
  Georeference& operator=(Georeference&&) noexcept;
  ~Georeference();

  /// World metres of a geodetic position; nothing when it cannot be projected (not finite, or
  /// outside the projection's domain).
  std::optional<glm::dvec3> toWorld(const GeodeticPosition& position) const;
  /// Geodetic position of world metres; nothing when they cannot be unprojected.
  std::optional<GeodeticPosition> toGeodetic(const glm::dvec3& worldM) const;

  /// True when world x, y are a database CRS's coordinates, false on the tangent plane.
  bool hasCrs() const noexcept;
  /// One line for people: the CRS's name and code ("WGS 84 / UTM zone 32N (EPSG:32632)") or
  /// "local tangent plane at 46.000000 N, 7.000000 E".
  const std::string& description() const noexcept;

 private:
  struct Impl;
  explicit Georeference(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> mImpl;
};

}  // namespace fieldcast::core
