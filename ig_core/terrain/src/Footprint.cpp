// The view's footprint for tile prefetch: convex hull (Andrew's monotone chain) and the
// separating-axis test of a convex polygon against a tile's rectangle.
#include "Footprint.h"

#include <glm/common.hpp>

#include <algorithm>

namespace fieldcast::core {
namespace {

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) noexcept {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

}  // namespace

// Andrew's monotone chain; `points` is reordered, the hull (counter-clockwise) left in `hull`.
void convexHull(std::vector<glm::dvec2>& points, std::vector<glm::dvec2>& hull) {
  std::sort(points.begin(), points.end(),
            [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  hull.clear();
  if (points.size() < 3) {
    hull = points;
    return;
  }
  hull.resize(2 * points.size());
  std::size_t k = 0;
  for (const glm::dvec2& p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i > 0; --i) {
    const glm::dvec2& p = points[i - 1];
    while (k >= lower && cross(hull[k - 2], hull[k - 1], p) <= 0.0) --k;
    hull[k++] = p;
  }
  hull.resize(k - 1);
}

// Separating-axis test between a convex polygon and an axis-aligned rectangle.
bool polygonTouchesRect(const std::vector<glm::dvec2>& hull, const glm::dvec2& lo, const glm::dvec2& hi) noexcept {
  if (hull.empty()) return false;
  glm::dvec2 bmin = hull[0], bmax = hull[0];
  for (const glm::dvec2& p : hull) {
    bmin = glm::min(bmin, p);
    bmax = glm::max(bmax, p);
  }
  if (bmax.x < lo.x || bmin.x > hi.x || bmax.y < lo.y || bmin.y > hi.y) return false;
  if (hull.size() < 3) return true;
  const glm::dvec2 corners[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  for (std::size_t e = 0; e < hull.size(); ++e) {
    const glm::dvec2& a = hull[e];
    const glm::dvec2& b = hull[(e + 1) % hull.size()];
    // Counter-clockwise hull: the polygon lies left of each edge; all corners right → separated.
    bool allOutside = true;
    for (const glm::dvec2& c : corners) {
      if (cross(a, b, c) >= 0.0) {
        allOutside = false;
        break;
      }
    }
    if (allOutside) return false;
  }
  return true;
}

}  // namespace fieldcast::core
