#pragma once
// The view's footprint on the ground for tile prefetch (TileCache::computeRequest): the convex hull
// of the points where the view's rays meet a plane, and its tests against a tile's rectangle. All
// in world metres (x east, y north).
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace fieldcast::core {

/// Convex hull of `points` (Andrew's monotone chain), counter-clockwise, into `hull`; `points` is
/// reordered. Allocates only when `hull` must grow.
void convexHull(std::vector<glm::dvec2>& points, std::vector<glm::dvec2>& hull);

/// Whether the convex polygon `hull` (counter-clockwise) touches the axis-aligned rectangle
/// [lo, hi] (separating-axis test).
bool polygonTouchesRect(const std::vector<glm::dvec2>& hull, const glm::dvec2& lo, const glm::dvec2& hi) noexcept;

/// Distance from `p` to the nearest point of the rectangle [lo, hi] (0 inside).
inline double distanceToRect(const glm::dvec2& p, const glm::dvec2& lo, const glm::dvec2& hi) noexcept {
  const double dx = std::max({lo.x - p.x, 0.0, p.x - hi.x});
  const double dy = std::max({lo.y - p.y, 0.0, p.y - hi.y});
  return std::sqrt(dx * dx + dy * dy);
}

/// Distance from `p` to the farthest corner of the rectangle [lo, hi].
inline double farthestInRect(const glm::dvec2& p, const glm::dvec2& lo, const glm::dvec2& hi) noexcept {
  const double dx = std::max(std::fabs(p.x - lo.x), std::fabs(p.x - hi.x));
  const double dy = std::max(std::fabs(p.y - lo.y), std::fabs(p.y - hi.y));
  return std::sqrt(dx * dx + dy * dy);
}

}  // namespace fieldcast::core
