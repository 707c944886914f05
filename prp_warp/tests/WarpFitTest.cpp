// The fits: exact recovery of a known quadratic, identity, pure roll, and the counted fallbacks.
#include "AnalyticScene.h"

#include <prp_warp/WarpFit.h>

#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fieldcast::warp {
namespace {

constexpr int kW = 320, kH = 240;
const MarginPx kMargin{32, 24};

Pose lookingDown() { return Pose{{100.0, -50.0, 300.0}, radians(20.0), radians(-25.0), 0.0}; }

Frame sceneFrame(const Pose& pose) {
  // A small render (ss = 1) is enough for geometry
  return test::renderFrame(pose, kW, kH, kMargin, radians(60.0), PixelFormat::Grey8, 1, false);
}

void expectMapsAgree(const QuadraticFit& fit, const auto& expected, double tolPx) {
  for (double v = 0.5; v < kH; v += 17.0)
    for (double u = 0.5; u < kW; u += 23.0) {
      const glm::dvec2 got = fit({u, v});
      const glm::dvec2 want = expected(glm::dvec2{u, v});
      ASSERT_NEAR(got.x, want.x, tolPx) << "at raster " << u << "," << v;
      ASSERT_NEAR(got.y, want.y, tolPx) << "at raster " << u << "," << v;
    }
}

TEST(FitQuadratic, RecoversAKnownQuadraticExactlyFromNinePoints) {
  QuadraticMap truth;
  truth.a = {12.5, 1.02, 0.03, 2e-5, -4e-5, 1.5e-5};
  truth.b = {-7.0, -0.02, 0.97, -3e-5, 2e-5, 6e-5};
  std::vector<glm::dvec2> raster, frame;
  for (double v : {20.0, 120.0, 220.0})
    for (double u : {16.0, 160.0, 304.0}) {
      raster.emplace_back(u, v);
      frame.push_back(truth({u, v}));
    }
  const auto fit = fitQuadratic(raster, frame, {160.0, 120.0}, 160.0);
  ASSERT_TRUE(fit.has_value());
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(fit->a[static_cast<std::size_t>(i)], truth.a[static_cast<std::size_t>(i)],
                1e-9 * std::max(1.0, std::abs(truth.a[static_cast<std::size_t>(i)])));
    EXPECT_NEAR(fit->b[static_cast<std::size_t>(i)], truth.b[static_cast<std::size_t>(i)],
                1e-9 * std::max(1.0, std::abs(truth.b[static_cast<std::size_t>(i)])));
  }
  for (double v = 0.5; v < 240.0; v += 13.0)
    for (double u = 0.5; u < 320.0; u += 11.0) {
      EXPECT_NEAR((*fit)({u, v}).x, truth({u, v}).x, 1e-8);
      EXPECT_NEAR((*fit)({u, v}).y, truth({u, v}).y, 1e-8);
    }
}

TEST(FitQuadratic, RefusesTooFewOrCollinearPoints) {
  std::vector<glm::dvec2> five{{0, 0}, {10, 0}, {0, 10}, {10, 10}, {5, 3}};
  EXPECT_FALSE(fitQuadratic(five, five, {5, 5}, 5.0).has_value());
  std::vector<glm::dvec2> line;
  for (int i = 0; i < 9; ++i) line.emplace_back(10.0 * i, 5.0 * i);
  EXPECT_FALSE(fitQuadratic(line, line, {40, 20}, 40.0).has_value());
}

TEST(FitFieldQuadratic, IdentityPoseGivesIdentityWarp) {
  const Frame f = sceneFrame(lookingDown());
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  const QuadraticFit fit = fitFieldQuadratic(f, f.pose, g);
  ASSERT_EQ(fit.outcome, FitOutcome::Quadratic);
  EXPECT_EQ(fit.usablePoints, 9);
  expectMapsAgree(
      fit,
      [&](glm::dvec2 p) {
        return p + glm::dvec2{kMargin.x, kMargin.y};
      },
      1e-6);
  EXPECT_NEAR(fit.quadratic.a[1], 1.0, 1e-9);
  EXPECT_NEAR(fit.quadratic.b[2], 1.0, 1e-9);
  for (int i : {3, 4, 5}) {
    EXPECT_NEAR(fit.quadratic.a[static_cast<std::size_t>(i)], 0.0, 1e-12);
    EXPECT_NEAR(fit.quadratic.b[static_cast<std::size_t>(i)], 0.0, 1e-12);
  }
}

TEST(FitFieldQuadratic, PureRollGivesARotationAboutThePrincipalPoint) {
  const Frame f = sceneFrame(lookingDown());
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  Pose rolled = f.pose;
  rolled.rollRad = radians(12.0);
  const QuadraticFit fit = fitFieldQuadratic(f, rolled, g);
  ASSERT_EQ(fit.outcome, FitOutcome::Quadratic);
  // No quadratic terms, and the linear part is a rotation by the roll angle
  for (int i : {3, 4, 5}) {
    EXPECT_NEAR(fit.quadratic.a[static_cast<std::size_t>(i)], 0.0, 1e-10);
    EXPECT_NEAR(fit.quadratic.b[static_cast<std::size_t>(i)], 0.0, 1e-10);
  }
  const double c = std::cos(radians(12.0)), s = std::sin(radians(12.0));
  EXPECT_NEAR(fit.quadratic.a[1], c, 1e-9);
  EXPECT_NEAR(fit.quadratic.b[2], c, 1e-9);
  EXPECT_NEAR(std::abs(fit.quadratic.a[2]), s, 1e-9);
  EXPECT_NEAR(fit.quadratic.a[2], -fit.quadratic.b[1], 1e-9);
  // Right wing down: the horizon in the field tilts so that a point right of centre appears
  // higher in the frame than in the field (frame y smaller), i.e. it maps up-and-right.
  const glm::dvec2 centre{g.raster.cxPx, g.raster.cyPx};
  const glm::dvec2 right = fit(centre + glm::dvec2{100.0, 0.0}) - fit(centre);
  EXPECT_NEAR(right.x, 100.0 * c, 1e-6);
  EXPECT_NEAR(std::abs(right.y), 100.0 * s, 1e-6);
  // The same as the exact rotation-only homography everywhere
  const Homography h = rotationHomography(f, rolled, g);
  expectMapsAgree(
      fit, [&](glm::dvec2 p) { return h(p); }, 1e-6);
  // And the principal point stays put
  EXPECT_NEAR(fit(centre).x, f.intrinsics.cxPx, 1e-9);
  EXPECT_NEAR(fit(centre).y, f.intrinsics.cyPx, 1e-9);
}

TEST(FitFieldQuadratic, FewerThanSixPointsFallBackToTheRotationHomography) {
  Frame f = sceneFrame(lookingDown());
  for (std::size_t i = 0; i < 4; ++i) f.controlPoints[i].kind = ControlPointKind::Missing;
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  Pose turned = f.pose;
  turned.headingRad += radians(2.0);
  const QuadraticFit fit = fitFieldQuadratic(f, turned, g);
  EXPECT_EQ(fit.outcome, FitOutcome::FallbackFewPoints);
  EXPECT_TRUE(fit.fellBack());
  EXPECT_EQ(fit.usablePoints, 5);
  const Homography h = rotationHomography(f, turned, g);
  expectMapsAgree(
      fit, [&](glm::dvec2 p) { return h(p); }, 1e-12);
}

TEST(FitFieldQuadratic, AllSkyFallsBackAndTheRotationHomographyIsExactForSky) {
  const Pose up{{0.0, 0.0, 100.0}, 0.0, radians(30.0), 0.0};  // looking well above the horizon
  const Frame f = sceneFrame(up);
  for (const ControlPoint& cp : f.controlPoints) ASSERT_EQ(cp.kind, ControlPointKind::Sky);
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  Pose moved = up;
  moved.positionM += glm::dvec3{30.0, 40.0, 5.0};  // translation does not move points at infinity
  moved.headingRad += radians(3.0);
  moved.rollRad = radians(5.0);
  const QuadraticFit fit = fitFieldQuadratic(f, moved, g);
  EXPECT_EQ(fit.outcome, FitOutcome::FallbackAllSky);
  // Every sky direction seen in the field lands where the frame saw it
  for (double v = 10.5; v < kH; v += 40.0)
    for (double u = 10.5; u < kW; u += 50.0) {
      const glm::dvec3 dir = pixelRay(moved, g.raster, {u, v});
      const auto truth = projectDirection(f.pose, f.intrinsics, dir);
      ASSERT_TRUE(truth.has_value());
      EXPECT_NEAR(fit({u, v}).x, truth->x, 1e-7);
      EXPECT_NEAR(fit({u, v}).y, truth->y, 1e-7);
    }
}

TEST(FitFieldQuadratic, PointsBehindTheCameraAreNotUsed) {
  const Frame f = sceneFrame(lookingDown());
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  Pose backwards = f.pose;
  backwards.headingRad += radians(180.0);
  backwards.pitchRad = radians(25.0);
  const QuadraticFit fit = fitFieldQuadratic(f, backwards, g);
  EXPECT_TRUE(fit.fellBack());
  EXPECT_LT(fit.usablePoints, 6);
}

TEST(FitHomography, RecoversAKnownHomographyAndFailsWhenDegenerate) {
  Homography truth;
  truth.h = {1.1, 0.05, 12.0, -0.03, 0.95, -4.0, 1e-4, -2e-4, 1.0};
  std::vector<glm::dvec2> raster, frame;
  for (double v : {10.0, 100.0, 230.0})
    for (double u : {10.0, 150.0, 310.0}) {
      raster.emplace_back(u, v);
      frame.push_back(truth({u, v}));
    }
  const auto h = fitHomography(raster, frame);
  ASSERT_TRUE(h.has_value());
  for (double v = 0.5; v < 240.0; v += 29.0)
    for (double u = 0.5; u < 320.0; u += 31.0) {
      EXPECT_NEAR((*h)({u, v}).x, truth({u, v}).x, 1e-6);
      EXPECT_NEAR((*h)({u, v}).y, truth({u, v}).y, 1e-6);
    }
  std::vector<glm::dvec2> three{{0, 0}, {1, 0}, {0, 1}};
  EXPECT_FALSE(fitHomography(three, three).has_value());
}

TEST(RotationHomography, MapsEveryDirectionExactlyUnderAnyRotation) {
  const Frame f = sceneFrame(lookingDown());
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  const Pose b{f.pose.positionM, f.pose.headingRad + 0.05, f.pose.pitchRad - 0.03, 0.2};
  const Homography h = rotationHomography(f, b, g);
  for (double v = 0.5; v < kH; v += 30.0)
    for (double u = 0.5; u < kW; u += 40.0) {
      const auto truth = projectDirection(f.pose, f.intrinsics, pixelRay(b, g.raster, {u, v}));
      ASSERT_TRUE(truth.has_value());
      EXPECT_NEAR(h({u, v}).x, truth->x, 1e-7);
      EXPECT_NEAR(h({u, v}).y, truth->y, 1e-7);
    }
}

// A field turned so far from its frame (a host jumping the heading or pitch) that a corner's ray lies
// behind the frame's camera: every pixel that sees in front of the frame's camera still maps there,
// the others have no sample. The maps were scaled by w at raster (0, 0): with that corner behind
// the camera w flipped sign everywhere, and the part of the field that sees the frame got nothing.
TEST(RotationHomography, AFieldTurnedPastItsFramesSideKeepsThePartInFront) {
  const Frame f = sceneFrame(Pose{{0.0, 0.0, 300.0}, 0.0, 0.0, 0.0});
  const OutputGeometry g = OutputGeometry::of(f, kW, kH);
  for (const double turnDeg : {75.0, -75.0}) {
    const Pose turned{f.pose.positionM, radians(turnDeg), radians(10.0), 0.0};
    const Homography h = rotationHomography(f, turned, g);
    int inFront = 0, behind = 0;
    std::vector<glm::dvec2> raster, frame;  // the pairs a fit of this turn would see
    for (double v = 0.5; v < kH; v += 16.0)
      for (double u = 0.5; u < kW; u += 16.0) {
        const auto truth = projectDirection(f.pose, f.intrinsics, pixelRay(turned, g.raster, {u, v}));
        const glm::dvec2 got = h({u, v});
        if (!truth) {
          ++behind;
          EXPECT_TRUE(std::isnan(got.x)) << turnDeg << "° at " << u << "," << v;
          continue;
        }
        ++inFront;
        EXPECT_NEAR(got.x, truth->x, 1e-6) << turnDeg << "° at " << u << "," << v;
        EXPECT_NEAR(got.y, truth->y, 1e-6) << turnDeg << "° at " << u << "," << v;
        raster.push_back({u, v});
        frame.push_back(*truth);
      }
    ASSERT_GT(inFront, 20) << turnDeg;
    ASSERT_GT(behind, 20) << turnDeg;  // the case at hand: part of the field sees behind the frame
    // The least-squares fit of the pairs in front is the same map, whatever its eigenvector's sign
    const auto fit = fitHomography(raster, frame);
    ASSERT_TRUE(fit.has_value()) << turnDeg;
    for (std::size_t i = 0; i < raster.size(); ++i) {
      EXPECT_NEAR((*fit)(raster[i]).x, frame[i].x, 1e-4) << turnDeg << "° at " << raster[i].x << "," << raster[i].y;
      EXPECT_NEAR((*fit)(raster[i]).y, frame[i].y, 1e-4) << turnDeg << "° at " << raster[i].x << "," << raster[i].y;
    }
  }
}

}  // namespace
}  // namespace fieldcast::warp
