// Warp quality on analytic scenes: a textured ground plane seen in a climb, a 30°/s banked turn
// and a 250 m/s low pass. Each frame is rendered at the pose of an earlier instant and warped to
// a field 100 ms later (a 15 Hz renderer with one frame of latency, mid-way through its fields);
// the field is compared with the exact rendering at the field's pose. Prints PSNR and the
// geometric error of the sampling map at held-out check pixels for every warp.
#include "AnalyticScene.h"

#include <prp_warp/Warps.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <map>

namespace fieldcast::warp {
namespace {

constexpr int kW = 320, kH = 240;
constexpr double kHfov = radians(60.0);

struct Scenario {
  const char* name;
  std::function<Pose(double)> pose;  // pose at time t (s)
};

/// Margin that covers the display window rolled by up to `rollRad`, plus 10 % for motion.
MarginPx marginFor(double rollRad) {
  const double c = std::abs(std::cos(rollRad)), s = std::abs(std::sin(rollRad));
  const double w = kW * c + kH * s, h = kW * s + kH * c;
  return {static_cast<int>(std::ceil((w - kW) / 2 + 0.1 * kW)), static_cast<int>(std::ceil((h - kH) / 2 + 0.1 * kH))};
}

std::vector<Scenario> scenarios() {
  const double g = 9.81;
  return {
      {"climb 100 m/s, 10 deg",
       [](double t) {
         const double v = 100.0, gamma = radians(10.0);
         return Pose{{0.0, v * std::cos(gamma) * t, 300.0 + v * std::sin(gamma) * t}, 0.0, radians(-15.0), 0.0};
       }},
      {"bank turn 30 deg/s",
       [g](double t) {
         const double v = 60.0, rate = radians(30.0), radius = v / rate;
         const double psi = rate * t;
         return Pose{{radius * (1.0 - std::cos(psi)), radius * std::sin(psi), 400.0},
                     psi,
                     radians(-20.0),
                     std::atan(v * rate / g)};
       }},
      {"low pass 250 m/s at 50 m",
       [](double t) {
         return Pose{{0.0, 250.0 * t, 50.0}, 0.0, radians(-8.0), 0.0};
       }},
  };
}

struct Score {
  double psnrDb = 0.0;
  double meanErrPx = 0.0;
  double maxErrPx = 0.0;
  std::uint32_t violations = 0;
};

Score evaluate(Warp& warp, const Frame& frame, const Pose& fieldPose, FieldParity parity, const Image& truth) {
  Image out(kW, fieldRowCount(parity, kH), frame.image.format());
  const WarpResult r = warp.warp(frame, fieldPose, parity, out);
  EXPECT_EQ(r.status, WarpStatus::Ok);
  Score s;
  s.psnrDb = test::psnr(out, truth);
  s.violations = r.marginViolations;
  // Held-out check pixels: a 13 × 9 grid on the field's rows, away from the 3 × 3 control grid
  const OutputGeometry g = OutputGeometry::of(frame, kW, kH);
  int n = 0;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 13; ++i) {
      const int row = rasterRow(parity, (fieldRowCount(parity, kH) * (2 * j + 1)) / 18);
      const glm::dvec2 p{(kW * (2 * i + 1)) / 26 + 0.5, row + 0.5};
      const auto truthPx = test::trueSourcePx(frame, fieldPose, g, p);
      const auto got = warp.sourcePx(p);
      if (!truthPx || !got) continue;
      const double e = glm::length(*got - *truthPx);
      s.meanErrPx += e;
      s.maxErrPx = std::max(s.maxErrPx, e);
      ++n;
    }
  s.meanErrPx /= std::max(n, 1);
  return s;
}

TEST(WarpQuality, QuadraticBeatsHoldClearlyOnAnalyticFlights) {
  constexpr double kFrameTimeS = 1.0, kAgeS = 0.1;
  std::printf("\n%-26s %-11s %9s %12s %11s %10s\n", "flight (frame age 100 ms)", "warp", "PSNR dB", "mean err px",
              "max err px", "violations");
  for (const Scenario& sc : scenarios()) {
    Pose framePose = sc.pose(kFrameTimeS);
    const double roll = framePose.rollRad;
    framePose.rollRad = 0.0;  // the IG renders without roll; the warp applies it
    const Frame frame = test::renderFrame(framePose, kW, kH, marginFor(roll), kHfov);
    const Pose fieldPose = sc.pose(kFrameTimeS + kAgeS);
    const FieldParity parity = FieldParity::Bottom;
    const Image truth = test::renderTruthField(frame, fieldPose, kW, kH, parity);

    std::map<WarpKind, Score> scores;
    for (WarpKind kind : {WarpKind::Hold, WarpKind::Quadratic, WarpKind::Homography, WarpKind::Range3d}) {
      auto warp = makeWarp(kind, kW, kH);
      const Score s = evaluate(*warp, frame, fieldPose, parity, truth);
      scores[kind] = s;
      std::printf("%-26s %-11s %9.2f %12.3f %11.3f %10u\n", sc.name, std::string(toString(kind)).c_str(), s.psnrDb,
                  s.meanErrPx, s.maxErrPx, s.violations);
    }
    const Score& hold = scores[WarpKind::Hold];
    const Score& quad = scores[WarpKind::Quadratic];
    EXPECT_GT(quad.psnrDb, hold.psnrDb + 3.0) << sc.name;
    EXPECT_LT(quad.meanErrPx, 0.25 * hold.meanErrPx) << sc.name;
    EXPECT_LT(scores[WarpKind::Range3d].meanErrPx, 0.6) << sc.name;  // exact geometry, up to splat rounding
  }
}

// A side screen of a flat wall (README, "Channels"): its window lies wholly right of the view axis
// (10° to 50°) and above it more than below, so its principal point is outside the image. Every
// warp maps it as it maps a centred one: at the frame's own pose the display window itself, and
// for an ownship turning and pitching up on the spot (so the rotation-only warp is exact too) as
// close to the truth as they come on the centred flights.
TEST(WarpQuality, EveryWarpHonoursAWindowOffTheViewAxis) {
  const Intrinsics display =
      Intrinsics::fromFrustum(kW, kH, FrustumAngles{radians(10.0), radians(50.0), radians(20.0), radians(-12.0)});
  ASSERT_LT(display.cxPx, 0.0);
  const auto flight = [](double t) {
    return Pose{{0.0, 0.0, 250.0}, radians(20.0) * t, radians(-30.0 + 8.0 * t), 0.0};
  };
  const Frame frame = test::renderFrame(flight(1.0), display, marginFor(0.0));
  const Pose fieldPose = flight(1.1);
  const FieldParity parity = FieldParity::Bottom;
  const Image truth = test::renderTruthField(frame, fieldPose, kW, kH, parity);
  std::map<WarpKind, Score> scores;
  for (WarpKind kind : {WarpKind::Hold, WarpKind::Quadratic, WarpKind::Homography, WarpKind::Mesh, WarpKind::Range3d,
                        WarpKind::Rotation}) {
    auto warp = makeWarp(kind, kW, kH);
    // At the frame's own pose: the display window, sample for sample
    const glm::dvec2 p{37.5, rasterRow(parity, 5) + 0.5};
    Image still(kW, fieldRowCount(parity, kH), PixelFormat::Rgb8);
    ASSERT_EQ(warp->warp(frame, frame.pose, parity, still).status, WarpStatus::Ok);
    const auto src = warp->sourcePx(p);
    ASSERT_TRUE(src.has_value());
    EXPECT_NEAR(src->x, p.x + frame.margin.x, 1e-6) << toString(kind);
    EXPECT_NEAR(src->y, p.y + frame.margin.y, 1e-6) << toString(kind);
    const Score s = evaluate(*warp, frame, fieldPose, parity, truth);
    scores[kind] = s;
    std::printf("off-axis window, %-11s %9.2f dB, mean error %.3f px, max %.3f px\n",
                std::string(toString(kind)).c_str(), s.psnrDb, s.meanErrPx, s.maxErrPx);
  }
  EXPECT_GT(scores[WarpKind::Hold].meanErrPx, 5.0);
  for (WarpKind kind : {WarpKind::Quadratic, WarpKind::Homography, WarpKind::Mesh, WarpKind::Rotation}) {
    EXPECT_LT(scores[kind].meanErrPx, 0.1) << toString(kind);
  }
  EXPECT_LT(scores[WarpKind::Range3d].meanErrPx, 0.6);  // exact geometry, up to splat rounding
}

}  // namespace
}  // namespace fieldcast::warp
