#include <motion/CubicSpline.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fieldcast::motion {

CubicSpline::CubicSpline(std::vector<double> s, std::vector<double> y) : mS(std::move(s)), mY(std::move(y)) {
  const std::size_t n = mS.size();
  if (n < 2 || mY.size() != n) {
    throw std::invalid_argument("spline: need at least 2 knots with one value each, got " + std::to_string(n) +
                                " knots and " + std::to_string(mY.size()) + " values");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(mS[i]) || !std::isfinite(mY[i]))
      throw std::invalid_argument("spline: knot values must be finite");
    if (i > 0 && !(mS[i] > mS[i - 1])) {
      throw std::invalid_argument("spline: knots must be strictly increasing (knot " + std::to_string(i) + ")");
    }
  }
  // Tridiagonal system for the second derivatives M_i with M_0 = M_{n-1} = 0 (Thomas algorithm).
  mSecond.assign(n, 0.0);
  if (n == 2) return;
  std::vector<double> diag(n, 0.0), rhs(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = mS[i] - mS[i - 1], h1 = mS[i + 1] - mS[i];
    diag[i] = 2.0 * (h0 + h1);
    rhs[i] = 6.0 * ((mY[i + 1] - mY[i]) / h1 - (mY[i] - mY[i - 1]) / h0);
  }
  // Forward sweep: the sub- and super-diagonals are the interval lengths.
  for (std::size_t i = 2; i + 1 < n; ++i) {
    const double sub = mS[i] - mS[i - 1];
    const double factor = sub / diag[i - 1];
    diag[i] -= factor * sub;
    rhs[i] -= factor * rhs[i - 1];
  }
  for (std::size_t i = n - 2; i >= 1; --i) {
    const double super = mS[i + 1] - mS[i];
    mSecond[i] = (rhs[i] - (i + 2 < n ? super * mSecond[i + 1] : 0.0)) / diag[i];
  }
}

SplineSample CubicSpline::sample(double s) const noexcept {
  const std::size_t n = mS.size();
  if (n == 0) return {};
  // Beyond the ends: the tangent line (y'' = 0 there by the natural condition).
  if (s <= mS.front() || s >= mS.back()) {
    const bool atStart = s <= mS.front();
    const std::size_t k = atStart ? 0 : n - 2;
    const double h = mS[k + 1] - mS[k];
    const double slopeAtEnd = atStart ? (mY[1] - mY[0]) / h - h * (2.0 * mSecond[0] + mSecond[1]) / 6.0
                                      : (mY[n - 1] - mY[n - 2]) / h + h * (mSecond[n - 2] + 2.0 * mSecond[n - 1]) / 6.0;
    const double s0 = atStart ? mS.front() : mS.back();
    const double y0 = atStart ? mY.front() : mY.back();
    return {y0 + slopeAtEnd * (s - s0), slopeAtEnd, 0.0};
  }
  // Interval [s_k, s_k+1] containing s.
  const auto it = std::upper_bound(mS.begin(), mS.end(), s);
  const std::size_t k = static_cast<std::size_t>(it - mS.begin()) - 1;
  const double h = mS[k + 1] - mS[k];
  const double a = (mS[k + 1] - s) / h, b = (s - mS[k]) / h;
  const double m0 = mSecond[k], m1 = mSecond[k + 1];
  SplineSample out;
  out.value = a * mY[k] + b * mY[k + 1] + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
  out.slope = (mY[k + 1] - mY[k]) / h + ((1.0 - 3.0 * a * a) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
  out.curvature = a * m0 + b * m1;
  return out;
}

}  // namespace fieldcast::motion
