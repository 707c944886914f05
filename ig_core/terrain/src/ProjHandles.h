#pragma once
// Owning handles for PROJ objects (a context per owner: PROJ objects are not thread-safe, and
// objects of different contexts may be used from different threads), and the one projection
// Fieldcast makes up itself: a local transverse Mercator.

#include <proj.h>
#include <proj_experimental.h>  // the CRS builders (a stable part of the API since PROJ 6)

#include <cstdio>
#include <memory>
#include <string>

namespace fieldcast::core::detail {

struct ProjContextDeleter {
  void operator()(PJ_CONTEXT* ctx) const noexcept { proj_context_destroy(ctx); }
};
struct ProjObjectDeleter {
  void operator()(PJ* pj) const noexcept { proj_destroy(pj); }
};
using ProjContext = std::unique_ptr<PJ_CONTEXT, ProjContextDeleter>;
using ProjObject = std::unique_ptr<PJ, ProjObjectDeleter>;

/// A fresh context that keeps PROJ's own log quiet (errors are reported by the caller).
inline ProjContext makeProjContext() {
  ProjContext ctx(proj_context_create());
  proj_log_level(ctx.get(), PJ_LOG_NONE);
  return ctx;
}

/// PROJ's text for the context's last error ("" when none).
inline std::string projError(PJ_CONTEXT* ctx) {
  const int err = proj_context_errno(ctx);
  const char* text = err != 0 ? proj_context_errno_string(ctx, err) : nullptr;
  return text != nullptr ? text : "";
}

/// A projected CRS: transverse Mercator centred at (lat0, lon0) in degrees, scale 1, no false
/// easting or northing, metres east and north, on the geodetic datum of `geographic`. Null on failure.
inline ProjObject localTransverseMercator(PJ_CONTEXT* ctx, const PJ* geographic, double lat0, double lon0) {
  const ProjObject geodetic(proj_crs_get_geodetic_crs(ctx, geographic));
  const ProjObject conversion(proj_create_conversion_transverse_mercator(ctx, lat0, lon0, 1.0, 0.0, 0.0, "degree",
                                                                         0.0174532925199433, "metre", 1.0));
  const ProjObject axes(proj_create_cartesian_2D_cs(ctx, PJ_CART2D_EASTING_NORTHING, "metre", 1.0));
  if (!geodetic || !conversion || !axes) return nullptr;
  char name[128];
  std::snprintf(name, sizeof name, "Local transverse Mercator at %.6f, %.6f on %s (Fieldcast)", lat0, lon0,
                proj_get_name(geodetic.get()) != nullptr ? proj_get_name(geodetic.get()) : "its datum");
  return ProjObject(proj_create_projected_crs(ctx, name, geodetic.get(), conversion.get(), axes.get()));
}

}  // namespace fieldcast::core::detail
