// Georeference: WGS 84 latitude/longitude ↔ world metres through PROJ (see Georeference.h).
#include <ig_core/Georeference.h>

#include "ProjHandles.h"

#include <cmath>
#include <cstdio>

namespace fieldcast::core {

using detail::ProjContext;
using detail::ProjObject;

struct Georeference::Impl {
  ProjContext ctx;
  ProjObject transform;  // WGS 84 (longitude, latitude) → world (x east, y north)
  bool hasCrs = false;
  std::string description;
};

namespace {

// From WGS 84 longitude/latitude to `crs`'s easting/northing, whatever the axis orders.
ProjObject transformFromWgs84(PJ_CONTEXT* ctx, const PJ* crs) {
  const ProjObject wgs84(proj_create(ctx, "EPSG:4326"));
  if (!wgs84) return nullptr;
  const ProjObject raw(proj_create_crs_to_crs_from_pj(ctx, wgs84.get(), crs, nullptr, nullptr));
  return raw ? ProjObject(proj_normalize_for_visualization(ctx, raw.get())) : nullptr;
}

std::string nameOf(const PJ* crs) {
  std::string text = proj_get_name(crs) != nullptr ? proj_get_name(crs) : "unnamed CRS";
  const char* authority = proj_get_id_auth_name(crs, 0);
  const char* code = proj_get_id_code(crs, 0);
  if (authority != nullptr && code != nullptr) text += std::string(" (") + authority + ":" + code + ")";
  return text;
}

bool finite(const PJ_COORD& c) { return std::isfinite(c.xy.x) && std::isfinite(c.xy.y) && c.xy.x != HUGE_VAL; }

}  // namespace

Georeference::Georeference(std::unique_ptr<Impl> impl) : mImpl(std::move(impl)) {}
Georeference::Georeference(Georeference&&) noexcept = default;
Georeference& Georeference::operator=(Georeference&&) noexcept = default;
Georeference::~Georeference() = default;

Georeference Georeference::fromCrs(const std::string& crsText) {
  auto impl = std::make_unique<Impl>();
  impl->ctx = detail::makeProjContext();
  PJ_CONTEXT* ctx = impl->ctx.get();
  const ProjObject crs(proj_create(ctx, crsText.c_str()));
  if (!crs || proj_is_crs(crs.get()) == 0) {
    throw GeoreferenceError("CRS '" + crsText.substr(0, 80) + "': not a coordinate reference system PROJ reads (" +
                            detail::projError(ctx) + ")");
  }
  const PJ_TYPE type = proj_get_type(crs.get());
  if (type == PJ_TYPE_GEOGRAPHIC_2D_CRS || type == PJ_TYPE_GEOGRAPHIC_3D_CRS || type == PJ_TYPE_GEOCENTRIC_CRS) {
    throw GeoreferenceError("CRS " + nameOf(crs.get()) + ": not projected; a database's world is in metres");
  }
  impl->transform = transformFromWgs84(ctx, crs.get());
  if (!impl->transform) {
    throw GeoreferenceError("CRS " + nameOf(crs.get()) + ": no transformation from WGS 84 (" + detail::projError(ctx) +
                            ")");
  }
  impl->hasCrs = true;
  impl->description = nameOf(crs.get());
  return Georeference(std::move(impl));
}

Georeference Georeference::tangentPlane(GeodeticOrigin origin) {
  if (!(std::fabs(origin.latitudeDeg) < 90.0) || !(std::fabs(origin.longitudeDeg) <= 180.0)) {
    throw GeoreferenceError("tangent plane origin " + std::to_string(origin.latitudeDeg) + ", " +
                            std::to_string(origin.longitudeDeg) + ": not a latitude and longitude in degrees");
  }
  auto impl = std::make_unique<Impl>();
  impl->ctx = detail::makeProjContext();
  PJ_CONTEXT* ctx = impl->ctx.get();
  const ProjObject wgs84(proj_create(ctx, "EPSG:4326"));
  const ProjObject plane(
      wgs84 ? detail::localTransverseMercator(ctx, wgs84.get(), origin.latitudeDeg, origin.longitudeDeg) : nullptr);
  if (plane) impl->transform = transformFromWgs84(ctx, plane.get());
  if (!impl->transform)
    throw GeoreferenceError("tangent plane: PROJ cannot set it up (" + detail::projError(ctx) + ")");
  char text[96];
  std::snprintf(text, sizeof text, "local tangent plane at %.6f %s, %.6f %s", std::fabs(origin.latitudeDeg),
                origin.latitudeDeg < 0.0 ? "S" : "N", std::fabs(origin.longitudeDeg),
                origin.longitudeDeg < 0.0 ? "W" : "E");
  impl->description = text;
  return Georeference(std::move(impl));
}

Georeference Georeference::forDatabase(const DatabaseLayout& layout, GeodeticOrigin origin) {
  return forTerrain(layout.crs, origin);
}

Georeference Georeference::forTerrain(const std::string& crs, GeodeticOrigin origin) {
  return crs.empty() ? tangentPlane(origin) : fromCrs(crs);
}

std::optional<glm::dvec3> Georeference::toWorld(const GeodeticPosition& p) const {
  if (!(std::fabs(p.latitudeDeg) <= 90.0) || !std::isfinite(p.longitudeDeg) || !std::isfinite(p.altitudeM)) {
    return std::nullopt;
  }
  const PJ_COORD c = proj_trans(mImpl->transform.get(), PJ_FWD, proj_coord(p.longitudeDeg, p.latitudeDeg, 0.0, 0.0));
  if (!finite(c)) {
    proj_errno_reset(mImpl->transform.get());
    return std::nullopt;
  }
  return glm::dvec3(c.xy.x, c.xy.y, p.altitudeM);
}

std::optional<GeodeticPosition> Georeference::toGeodetic(const glm::dvec3& worldM) const {
  if (!std::isfinite(worldM.x) || !std::isfinite(worldM.y) || !std::isfinite(worldM.z)) return std::nullopt;
  const PJ_COORD c = proj_trans(mImpl->transform.get(), PJ_INV, proj_coord(worldM.x, worldM.y, 0.0, 0.0));
  if (!finite(c)) {
    proj_errno_reset(mImpl->transform.get());
    return std::nullopt;
  }
  return GeodeticPosition{c.lp.phi, c.lp.lam, worldM.z};
}

bool Georeference::hasCrs() const noexcept { return mImpl->hasCrs; }

const std::string& Georeference::description() const noexcept { return mImpl->description; }

}  // namespace fieldcast::core
