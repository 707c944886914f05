#pragma once
// A natural cubic spline y(s) through knots (s_i, y_i): C² everywhere, straight lines beyond the
// ends (the natural end condition makes y'' = 0 there, so the extension stays C²).

#include <vector>

namespace fieldcast::motion {

/// Value and first two derivatives of a spline at one parameter.
struct SplineSample {
  double value = 0.0;
  double slope = 0.0;      ///< dy/ds
  double curvature = 0.0;  ///< d²y/ds²
};

/// Natural cubic interpolating spline over strictly increasing knots.
class CubicSpline {
 public:
  CubicSpline() = default;
  /// Fits the spline. Throws std::invalid_argument unless there are ≥ 2 knots, sizes match and
  /// `s` is strictly increasing and finite.
  CubicSpline(std::vector<double> s, std::vector<double> y);

  /// y, y', y'' at `s`; linear beyond the ends. RT-safe (no allocation; binary search).
  SplineSample sample(double s) const noexcept;

 private:
  std::vector<double> mS;
  std::vector<double> mY;
  std::vector<double> mSecond;  // y'' at each knot
};

}  // namespace fieldcast::motion
