#include <motion/CubicSpline.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace fieldcast::motion {
namespace {

TEST(CubicSpline, PassesThroughItsKnots) {
  const std::vector<double> s{0.0, 1.0, 2.5, 4.0, 7.0};
  const std::vector<double> y{3.0, -1.0, 2.0, 8.0, 0.5};
  const CubicSpline spline(s, y);
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_NEAR(spline.sample(s[i]).value, y[i], 1e-12);
}

TEST(CubicSpline, ReproducesStraightLinesExactly) {
  const CubicSpline spline({0.0, 2.0, 3.0, 10.0}, {1.0, 5.0, 7.0, 21.0});  // y = 2s + 1
  for (double s = -5.0; s <= 15.0; s += 0.37) {
    const SplineSample q = spline.sample(s);
    EXPECT_NEAR(q.value, 2.0 * s + 1.0, 1e-9);
    EXPECT_NEAR(q.slope, 2.0, 1e-9);
    EXPECT_NEAR(q.curvature, 0.0, 1e-9);
  }
}

TEST(CubicSpline, IsTwiceContinuouslyDifferentiableAtKnots) {
  const std::vector<double> s{0.0, 1.0, 2.5, 4.0, 7.0};
  const CubicSpline spline(s, {3.0, -1.0, 2.0, 8.0, 0.5});
  const double e = 1e-7;
  for (std::size_t i = 1; i + 1 < s.size(); ++i) {
    const SplineSample left = spline.sample(s[i] - e), right = spline.sample(s[i] + e);
    EXPECT_NEAR(left.value, right.value, 1e-5);
    EXPECT_NEAR(left.slope, right.slope, 1e-5);
    EXPECT_NEAR(left.curvature, right.curvature, 1e-4);
  }
}

TEST(CubicSpline, NaturalEndsContinueAsTangentLines) {
  const CubicSpline spline({0.0, 1.0, 2.0}, {0.0, 1.0, 0.0});
  const SplineSample end = spline.sample(2.0);
  const SplineSample beyond = spline.sample(3.0);
  EXPECT_NEAR(beyond.value, end.value + end.slope, 1e-12);
  EXPECT_NEAR(beyond.slope, end.slope, 1e-12);
  EXPECT_NEAR(spline.sample(2.0 - 1e-9).curvature, 0.0, 1e-6);  // natural: y'' = 0 at the end
  // The analytic second derivative agrees with a finite difference inside.
  const double h = 1e-4;
  const double fd =
      (spline.sample(0.7 + h).value - 2 * spline.sample(0.7).value + spline.sample(0.7 - h).value) / (h * h);
  EXPECT_NEAR(spline.sample(0.7).curvature, fd, 1e-3);
}

TEST(CubicSpline, RejectsBadKnots) {
  EXPECT_THROW(CubicSpline({0.0}, {1.0}), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, 1.0}, {1.0}), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, 0.0}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(CubicSpline({0.0, NAN}, {1.0, 2.0}), std::invalid_argument);
}

}  // namespace
}  // namespace fieldcast::motion
