#include <fieldcast/Frame.h>

#include <stdexcept>
#include <string>

namespace fieldcast {

std::vector<glm::dvec2> controlGridFramePx(int displayWidthPx, int displayHeightPx, MarginPx margin, int perSide,
                                           double insetFraction) {
  if (perSide < 2)
    throw std::invalid_argument("control grid: need at least 2 points per side, got " + std::to_string(perSide));
  if (!(insetFraction >= 0.0 && insetFraction < 0.5)) {
    throw std::invalid_argument("control grid: inset fraction must be in [0, 0.5), got " +
                                std::to_string(insetFraction));
  }
  std::vector<glm::dvec2> points;
  points.reserve(static_cast<std::size_t>(perSide) * static_cast<std::size_t>(perSide));
  for (int row = 0; row < perSide; ++row) {
    const double fy = insetFraction + (1.0 - 2.0 * insetFraction) * row / (perSide - 1);
    for (int col = 0; col < perSide; ++col) {
      const double fx = insetFraction + (1.0 - 2.0 * insetFraction) * col / (perSide - 1);
      points.emplace_back(margin.x + fx * displayWidthPx, margin.y + fy * displayHeightPx);
    }
  }
  return points;
}

}  // namespace fieldcast
