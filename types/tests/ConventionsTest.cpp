// Golden projections: the conventions of DESIGN.md §6 worked out by hand for a few poses.
#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace fieldcast {
namespace {

// 640×480 with a 90° horizontal field of view: fx = fy = 320, principal point (320, 240).
const Intrinsics kCamera = Intrinsics::fromHorizontalFov(640, 480, radians(90.0));

void expectPixel(const std::optional<glm::dvec2>& px, double u, double v) {
  ASSERT_TRUE(px.has_value());
  EXPECT_NEAR(px->x, u, 1e-9);
  EXPECT_NEAR(px->y, v, 1e-9);
}

TEST(Intrinsics, FromHorizontalFov) {
  EXPECT_NEAR(kCamera.fxPx, 320.0, 1e-12);
  EXPECT_NEAR(kCamera.fyPx, 320.0, 1e-12);
  EXPECT_EQ(kCamera.cxPx, 320.0);
  EXPECT_EQ(kCamera.cyPx, 240.0);
  EXPECT_NEAR(kCamera.horizontalFovRad(), radians(90.0), 1e-12);
}

// A frustum's half-angles: the symmetric 90° one is kCamera; an asymmetric one puts the rays at
// its angles on the window's edges (projected through the camera conventions), and back.
TEST(Intrinsics, FromFrustumPutsTheEdgeAnglesOnTheEdges) {
  const Intrinsics symmetric =
      Intrinsics::fromFrustum(640, 480, {radians(-45.0), radians(45.0), std::atan(0.75), -std::atan(0.75)});
  EXPECT_NEAR(symmetric.fxPx, kCamera.fxPx, 1e-9);
  EXPECT_NEAR(symmetric.fyPx, kCamera.fyPx, 1e-9);
  EXPECT_NEAR(symmetric.cxPx, kCamera.cxPx, 1e-9);
  EXPECT_NEAR(symmetric.cyPx, kCamera.cyPx, 1e-9);

  const FrustumAngles angles{radians(-40.0), radians(15.0), radians(20.0), radians(-30.0)};
  const Intrinsics k = Intrinsics::fromFrustum(640, 480, angles);
  const Pose pose{};  // looking north, level: x east, y north, z up
  const auto atAngles = [](double azimuthRad, double elevationRad) {
    return glm::dvec3{std::tan(azimuthRad), 1.0, std::tan(elevationRad)} * 100.0;
  };
  expectPixel(projectPoint(pose, k, atAngles(angles.leftRad, 0.0)), 0.0, k.cyPx);
  expectPixel(projectPoint(pose, k, atAngles(angles.rightRad, 0.0)), 640.0, k.cyPx);
  expectPixel(projectPoint(pose, k, atAngles(0.0, angles.topRad)), k.cxPx, 0.0);
  expectPixel(projectPoint(pose, k, atAngles(0.0, angles.bottomRad)), k.cxPx, 480.0);
  const FrustumAngles back = k.frustum();
  EXPECT_NEAR(back.leftRad, angles.leftRad, 1e-12);
  EXPECT_NEAR(back.rightRad, angles.rightRad, 1e-12);
  EXPECT_NEAR(back.topRad, angles.topRad, 1e-12);
  EXPECT_NEAR(back.bottomRad, angles.bottomRad, 1e-12);
}

TEST(Intrinsics, MarginKeepsFocalAndShiftsCentre) {
  const Intrinsics framed = kCamera.withMargin(64, 48);
  EXPECT_EQ(framed.widthPx, 768);
  EXPECT_EQ(framed.heightPx, 576);
  EXPECT_EQ(framed.fxPx, kCamera.fxPx);
  EXPECT_EQ(framed.cxPx, 384.0);
  EXPECT_EQ(framed.cyPx, 288.0);
  // A point lands on the same display pixel, shifted by the margin.
  const Pose pose{};
  const glm::dvec3 p{30.0, 100.0, -20.0};
  const auto a = projectPoint(pose, kCamera, p);
  const auto b = projectPoint(pose, framed, p);
  ASSERT_TRUE(a && b);
  EXPECT_NEAR(b->x - a->x, 64.0, 1e-9);
  EXPECT_NEAR(b->y - a->y, 48.0, 1e-9);
}

TEST(Conventions, ZeroAttitudeLooksNorthWithEastRightAndUpUp) {
  const CameraAxes a = cameraAxes(Pose{});
  EXPECT_EQ(a.forward, glm::dvec3(0, 1, 0));
  EXPECT_EQ(a.right, glm::dvec3(1, 0, 0));
  EXPECT_EQ(a.up, glm::dvec3(0, 0, 1));
}

TEST(Conventions, GoldenProjectionsLevelNorth) {
  const Pose pose{};
  expectPixel(projectPoint(pose, kCamera, {0, 100, 0}), 320, 240);    // straight ahead: centre
  expectPixel(projectPoint(pose, kCamera, {100, 100, 0}), 640, 240);  // 45° east: right edge
  expectPixel(projectPoint(pose, kCamera, {0, 100, 50}), 320, 80);    // above: higher (smaller v)
  expectPixel(projectPoint(pose, kCamera, {-50, 200, -100}), 240, 400);
  EXPECT_FALSE(projectPoint(pose, kCamera, {0, -100, 0}).has_value());  // behind
}

TEST(Conventions, HeadingIsClockwiseFromNorth) {
  const Pose east{{0, 0, 0}, radians(90.0), 0, 0};
  expectPixel(projectPoint(east, kCamera, {100, 0, 0}), 320, 240);
  expectPixel(projectPoint(east, kCamera, {100, -100, 0}), 640, 240);  // facing east, south is right
  const Pose southWest{{0, 0, 0}, radians(225.0), 0, 0};
  expectPixel(projectPoint(southWest, kCamera, {-70, -70, 0}), 320, 240);
}

TEST(Conventions, PitchDownNinetyPutsNorthAtTheTop) {
  const Pose down{{0, 0, 1000}, 0.0, radians(-90.0), 0.0};
  expectPixel(projectPoint(down, kCamera, {0, 0, 0}), 320, 240);
  expectPixel(projectPoint(down, kCamera, {0, 100, 0}), 320, 208);  // north: up in the image
  expectPixel(projectPoint(down, kCamera, {100, 0, 0}), 352, 240);  // east: right
}

TEST(Conventions, PitchUpRaisesTheView) {
  const Pose up{{0, 0, 0}, 0.0, radians(45.0), 0.0};
  expectPixel(projectPoint(up, kCamera, {0, 100, 100}), 320, 240);
  expectPixel(projectPoint(up, kCamera, {0, 100, 0}), 320, 560);  // level point drops by tan45·fx
}

TEST(Conventions, RollRightWingDownRaisesTheRightHorizon) {
  const Pose banked{{0, 0, 0}, 0.0, 0.0, radians(30.0)};
  const CameraAxes a = cameraAxes(banked);
  EXPECT_LT(a.right.z, 0.0);  // right wing down
  EXPECT_GT(a.up.x, 0.0);     // head leans right
  // A level point ahead-right sits above the image centre: the horizon tilts up on the right.
  const double c30 = std::cos(radians(30.0)), s30 = std::sin(radians(30.0));
  expectPixel(projectPoint(banked, kCamera, {100, 100, 0}), 320 + 320 * c30, 240 - 320 * s30);
}

TEST(Conventions, AxesAreOrthonormalAndRightHanded) {
  for (double h : {0.0, 37.0, 181.0, 300.0}) {
    for (double p : {-89.0, -30.0, 0.0, 12.0}) {
      for (double r : {-60.0, 0.0, 25.0}) {
        const CameraAxes a = cameraAxes({{0, 0, 0}, radians(h), radians(p), radians(r)});
        EXPECT_NEAR(glm::length(a.right), 1.0, 1e-12);
        EXPECT_NEAR(glm::length(a.up), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(a.right, a.up), 0.0, 1e-12);
        EXPECT_NEAR(glm::dot(a.right, a.forward), 0.0, 1e-12);
        // right × forward = up (x east, y north, z up is right-handed).
        const glm::dvec3 c = glm::cross(a.right, a.forward);
        EXPECT_NEAR(glm::length(c - a.up), 0.0, 1e-12);
      }
    }
  }
}

TEST(Conventions, PixelRayAndProjectionAreInverse) {
  const Pose pose{{1234.5, -987.0, 350.0}, radians(211.0), radians(-17.0), radians(8.0)};
  const Intrinsics framed = kCamera.withMargin(32, 24);
  for (int j = 0; j < framed.heightPx; j += 37) {
    for (int i = 0; i < framed.widthPx; i += 41) {
      const glm::dvec2 px = pixelCentre(i, j);
      const glm::dvec3 ray = pixelRay(pose, framed, px);
      EXPECT_NEAR(glm::length(ray), 1.0, 1e-12);
      expectPixel(projectPoint(pose, framed, pose.positionM + 500.0 * ray), px.x, px.y);
      expectPixel(projectDirection(pose, framed, ray), px.x, px.y);
    }
  }
}

TEST(Conventions, RotationMatrixMatchesAxes) {
  const Pose pose{{10, 20, 30}, radians(70.0), radians(-20.0), radians(15.0)};
  const glm::dvec3 p{400.0, -35.0, 12.0};
  const glm::dvec3 viaMatrix = worldToCameraRotation(pose) * (p - pose.positionM);
  const glm::dvec3 viaAxes = worldToCamera(pose, p);
  EXPECT_NEAR(glm::length(viaMatrix - viaAxes), 0.0, 1e-9);
}

TEST(Conventions, PixelCentresAreHalfIntegers) {
  EXPECT_EQ(pixelCentre(0, 0), glm::dvec2(0.5, 0.5));
  EXPECT_EQ(pixelCentre(639, 479), glm::dvec2(639.5, 479.5));
}

TEST(ViewOffset, ZeroOffsetIsTheOwnshipToTheBit) {
  const Pose own{{1.5, -2.25, 300.0}, 2.9, -0.3, 0.7};
  EXPECT_EQ(offsetPose(own, ViewOffset{}), own);
}

TEST(ViewOffset, LevelOwnshipAddsYawAndPitchAndMovesInBodyAxes) {
  const Pose own{{100.0, 200.0, 50.0}, radians(90.0), 0.0, 0.0};  // facing east
  ViewOffset side;
  side.headingRad = radians(45.0);   // a right-hand channel
  side.positionM = {0.0, 2.0, 1.0};  // 2 m forward (east), 1 m up
  const Pose p = offsetPose(own, side);
  EXPECT_NEAR(p.headingRad, radians(135.0), 1e-12);
  EXPECT_NEAR(p.pitchRad, 0.0, 1e-12);
  EXPECT_NEAR(p.rollRad, 0.0, 1e-12);
  EXPECT_NEAR(p.positionM.x, 102.0, 1e-12);
  EXPECT_NEAR(p.positionM.y, 200.0, 1e-12);
  EXPECT_NEAR(p.positionM.z, 51.0, 1e-12);
  ViewOffset down;
  down.pitchRad = radians(-20.0);
  EXPECT_NEAR(offsetPose(own, down).pitchRad, radians(-20.0), 1e-12);
}

TEST(ViewOffset, AxesAreTheOwnshipAxesTimesTheOffsetAxes) {
  // Whatever the attitudes, the view's camera axes are the offset's axes carried into the ownship's frame.
  for (const Pose& own : {Pose{{}, 0.4, 0.2, -0.5}, Pose{{}, -2.8, -0.6, 1.1}, Pose{{}, 1.9, 0.05, 0.0}}) {
    for (const ViewOffset& off :
         {ViewOffset{{}, 0.7, 0.0, 0.0}, ViewOffset{{}, -0.3, 0.25, 0.4}, ViewOffset{{}, 0.0, 0.0, -0.9}}) {
      const CameraAxes o = cameraAxes(own);
      const CameraAxes r = cameraAxes(Pose{{}, off.headingRad, off.pitchRad, off.rollRad});
      auto carry = [&](const glm::dvec3& v) { return v.x * o.right + v.y * o.forward + v.z * o.up; };
      const CameraAxes got = cameraAxes(offsetPose(own, off));
      for (const auto& [a, b] : {std::pair{got.right, carry(r.right)}, std::pair{got.up, carry(r.up)},
                                 std::pair{got.forward, carry(r.forward)}}) {
        EXPECT_NEAR(glm::length(a - b), 0.0, 1e-12);
      }
    }
  }
}

}  // namespace
}  // namespace fieldcast
