#pragma once
// The two closed-form maps the warps resample through, both from output raster pixels (u, v)
// (continuous, origin top-left, pixel centres at half-integers) to frame pixels (margin included).

#include <glm/vec2.hpp>

#include <array>

namespace fieldcast::warp {

/// f(u, v) = (a·m, b·m) with monomials m = (1, u, v, u·v, u², v²) (DESIGN.md §3).
struct QuadraticMap {
  std::array<double, 6> a{};  ///< coefficients of the frame x coordinate
  std::array<double, 6> b{};  ///< coefficients of the frame y coordinate

  /// Frame pixel sampled for raster pixel `rasterPx`. RT-safe.
  constexpr glm::dvec2 operator()(glm::dvec2 rasterPx) const noexcept {
    const double u = rasterPx.x, v = rasterPx.y;
    const std::array<double, 6> m{1.0, u, v, u * v, u * u, v * v};
    double x = 0.0, y = 0.0;
    for (int i = 0; i < 6; ++i) {
      x += a[i] * m[i];
      y += b[i] * m[i];
    }
    return {x, y};
  }

  /// The affine map frame = offset + scale · raster (no warp, only the raster-to-frame scaling).
  static constexpr QuadraticMap affine(glm::dvec2 offsetPx, glm::dvec2 scale) noexcept {
    QuadraticMap q;
    q.a = {offsetPx.x, scale.x, 0.0, 0.0, 0.0, 0.0};
    q.b = {offsetPx.y, 0.0, scale.y, 0.0, 0.0, 0.0};
    return q;
  }
};

/// A plane projective map: frame = (h0 u + h1 v + h2, h3 u + h4 v + h5) / (h6 u + h7 v + h8).
struct Homography {
  std::array<double, 9> h{1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};  ///< row-major 3×3

  /// Frame pixel for raster pixel `rasterPx`; NaN when it maps to or behind infinity. RT-safe.
  glm::dvec2 operator()(glm::dvec2 rasterPx) const noexcept {
    const double u = rasterPx.x, v = rasterPx.y;
    const double w = h[6] * u + h[7] * v + h[8];
    if (!(w > 0.0)) return {kNan, kNan};
    return {(h[0] * u + h[1] * v + h[2]) / w, (h[3] * u + h[4] * v + h[5]) / w};
  }

  static constexpr double kNan = __builtin_nan("");
};

}  // namespace fieldcast::warp
