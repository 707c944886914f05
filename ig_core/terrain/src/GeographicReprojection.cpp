// reprojectGeographic(): a DEM in degrees onto a square metric grid. Square voxels of the geometric
// mean spacing over a grid in degrees distort it (1.5× at 50° N: a degree of longitude is shorter
// than one of latitude), so the grid is resampled in a transverse Mercator projection centred on
// it, on the source's own datum: scale 1 + x²/2R² at x from the central meridian (1.1e-5 at 30 km).
// Sampling is bilinear over the valid neighbours, as everywhere else in the importer.
#include "ElevationReaders.h"
#include "ProjHandles.h"

#include <spdlog/spdlog.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldcast::core::detail {

RawElevation reprojectGeographic(const RawElevation& degrees, const GeographicPlacement& p,
                                 const std::filesystem::path& path) {
  const std::string name = path.string();
  const ProjContext ctx = makeProjContext();
  const ProjObject source(proj_create(ctx.get(), p.crs.c_str()));
  if (!source || proj_get_type(source.get()) != PJ_TYPE_GEOGRAPHIC_2D_CRS) {
    throw ImportError(name + ": " + p.crs + " is not a geographic CRS PROJ knows (" + projError(ctx.get()) + ")");
  }
  const int w = degrees.width, h = degrees.height;
  const double lon0 = p.westDeg + 0.5 * w * p.stepXDeg;
  const double lat0 = p.northDeg - 0.5 * h * p.stepYDeg;
  if (!(std::fabs(lat0) < 84.0) || p.stepXDeg * w > 20.0) {
    throw ImportError(name + ": a geographic grid centred at latitude " + std::to_string(lat0) + " spanning " +
                      std::to_string(p.stepXDeg * w) +
                      " degrees of longitude does not fit one local projection (at most 20 degrees wide, "
                      "within 84 degrees of the equator)");
  }
  const ProjObject target = localTransverseMercator(ctx.get(), source.get(), lat0, lon0);
  const ProjObject raw(target ? proj_create_crs_to_crs_from_pj(ctx.get(), source.get(), target.get(), nullptr, nullptr)
                              : nullptr);
  const ProjObject transform(raw ? proj_normalize_for_visualization(ctx.get(), raw.get()) : nullptr);  // lon, lat
  const char* const wktOptions[] = {"MULTILINE=NO", nullptr};
  const char* wkt = target ? proj_as_wkt(ctx.get(), target.get(), PJ_WKT2_2019, wktOptions) : nullptr;
  if (!transform || wkt == nullptr) {
    throw ImportError(name + ": cannot set up the projection from " + p.crs + ": " + projError(ctx.get()));
  }

  // Source voxel centre (i, j), j counted from the south.
  const auto lonOf = [&](double i) { return p.westDeg + (i + 0.5) * p.stepXDeg; };
  const auto latOf = [&](double j) { return p.northDeg - (h - 0.5 - j) * p.stepYDeg; };
  const auto forward = [&](double lon, double lat) {
    const PJ_COORD c = proj_trans(transform.get(), PJ_FWD, proj_coord(lon, lat, 0.0, 0.0));
    return glm::dvec2(c.xy.x, c.xy.y);
  };
  // Metric pitch of one source step at the centre; the target's square voxel keeps their product.
  const double dx = glm::length(forward(lon0 + 0.5 * p.stepXDeg, lat0) - forward(lon0 - 0.5 * p.stepXDeg, lat0));
  const double dy = glm::length(forward(lon0, lat0 + 0.5 * p.stepYDeg) - forward(lon0, lat0 - 0.5 * p.stepYDeg));
  const double spacing = std::sqrt(dx * dy);
  // Extent: the projected voxel centres along the source's edges.
  glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  const auto include = [&](double i, double j) {
    const glm::dvec2 xy = forward(lonOf(i), latOf(j));
    lo = glm::min(lo, xy);
    hi = glm::max(hi, xy);
  };
  for (int i = 0; i < w; ++i) {
    include(i, 0);
    include(i, h - 1);
  }
  for (int j = 0; j < h; ++j) {
    include(0, j);
    include(w - 1, j);
  }
  if (!std::isfinite(lo.x) || !std::isfinite(hi.y) || !(spacing > 0.0)) {
    throw ImportError(name + ": the grid does not project (" + projError(ctx.get()) + ")");
  }
  const double widthVox = std::floor((hi.x - lo.x) / spacing + 1e-9) + 1.0;
  const double heightVox = std::floor((hi.y - lo.y) / spacing + 1e-9) + 1.0;
  if (widthVox > kMaxDatabaseSideVox || heightVox > kMaxDatabaseSideVox) {
    throw ImportError(name + ": reprojected grid of " + std::to_string(widthVox) + "x" + std::to_string(heightVox) +
                      " voxels is larger than a database holds");
  }
  RawElevation out;
  out.width = static_cast<int>(widthVox);
  out.height = static_cast<int>(heightVox);
  out.spacingM = spacing;
  const glm::dvec2 origin = 0.5 * (lo + hi) - 0.5 * glm::dvec2(out.width - 1, out.height - 1) * spacing;
  out.originM = origin;
  out.crs = wkt;
  const auto count = static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
  out.heightsM.assign(count, 0.0f);
  out.valid.assign(count, 0);

  std::vector<double> xs(static_cast<std::size_t>(out.width)), ys(xs.size());
  for (int j = 0; j < out.height; ++j) {
    for (int i = 0; i < out.width; ++i) {
      xs[static_cast<std::size_t>(i)] = origin.x + i * spacing;
      ys[static_cast<std::size_t>(i)] = origin.y + j * spacing;
    }
    proj_trans_generic(transform.get(), PJ_INV, xs.data(), sizeof(double), xs.size(), ys.data(), sizeof(double),
                       ys.size(), nullptr, 0, 0, nullptr, 0, 0);
    for (int i = 0; i < out.width; ++i) {
      // Fractional source position; half a voxel beyond the outer centres still lies in the data.
      double si = (xs[static_cast<std::size_t>(i)] - p.westDeg) / p.stepXDeg - 0.5;
      double sj = h - 0.5 - (p.northDeg - ys[static_cast<std::size_t>(i)]) / p.stepYDeg;
      if (!(si >= -0.5 && si <= w - 0.5 && sj >= -0.5 && sj <= h - 0.5)) continue;
      si = std::clamp(si, 0.0, w - 1.0);
      sj = std::clamp(sj, 0.0, h - 1.0);
      const int i0 = std::min(static_cast<int>(si), w - 2), j0 = std::min(static_cast<int>(sj), h - 2);
      const double tx = si - i0, ty = sj - j0;
      double sum = 0.0, weight = 0.0;
      for (int dj = 0; dj < 2; ++dj) {
        for (int di = 0; di < 2; ++di) {
          const std::size_t k =
              static_cast<std::size_t>(j0 + dj) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i0 + di);
          const double wk = (di != 0 ? tx : 1.0 - tx) * (dj != 0 ? ty : 1.0 - ty);
          if (degrees.valid[k] != 0 && wk > 0.0) {
            sum += wk * degrees.heightsM[k];
            weight += wk;
          }
        }
      }
      if (weight > 0.0) {
        const std::size_t k =
            static_cast<std::size_t>(j) * static_cast<std::size_t>(out.width) + static_cast<std::size_t>(i);
        out.heightsM[k] = static_cast<float>(sum / weight);
        out.valid[k] = 1;
      }
    }
  }
  spdlog::info(
      "{}: geographic ({}) {}x{} at {:.6g} x {:.6g} degrees ({:.1f} x {:.1f} m at the centre), "
      "reprojected to a transverse Mercator at {:.6f}, {:.6f}: {}x{} voxels of {:.3f} m",
      name, p.crs, w, h, p.stepXDeg, p.stepYDeg, dx, dy, lat0, lon0, out.width, out.height, spacing);
  return out;
}

}  // namespace fieldcast::core::detail
