// A channel's view from [view] (ChannelView.h), rendered: three yawed channels with off-axis windows
// whose edges abut continue across their seams as one wide window does, and a stereo pair's
// images show a point at a known depth with the disparity its eye separation predicts.
#include "ChannelView.h"

#include <ig_core/Renderer.h>
#include <ig_core/SyntheticTerrain.h>

#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <vector>

namespace fieldcast::app {
namespace {

const core::MemoryTerrain& hills() {
  static const std::unique_ptr<core::MemoryTerrain> terrain =
      core::makeSyntheticTerrain({core::SyntheticKind::Hills, 512, 2.0, 6, 3});
  return *terrain;
}

// A level ownship 20 m over the middle of the hills, looking north-east: terrain below the
// horizon, hills against the sky.
Pose ownship() {
  Pose p;
  p.positionM = {512.0, 512.0, hills().view().heightAtM(512.0, 512.0) + 20.0};
  p.headingRad = radians(35.0);
  return p;
}

// The display window of a channel: its range image (metres, +inf for the sky), row by row.
struct Window {
  int widthPx = 0, heightPx = 0;
  std::vector<float> rangeM;
  Pose pose;
  Intrinsics display;
  float at(int u, int v) const { return rangeM[static_cast<std::size_t>(v) * widthPx + u]; }
};

Window render(const ChannelView& view, const Pose& ship) {
  core::RenderSettings settings;
  settings.rangeImage = true;
  core::Renderer renderer(hills().view(), settings, 2);
  core::ViewRequest request;
  request.pose = offsetPose(ship, view.offset);
  request.display = view.display;
  const Frame frame = renderer.render(request);
  Window w{frame.displayWidthPx(), frame.displayHeightPx(), {}, frame.pose, view.display};
  for (int v = 0; v < w.heightPx; ++v)
    for (int u = 0; u < w.widthPx; ++u)
      w.rangeM.push_back(frame.rangeM[static_cast<std::size_t>(v + frame.margin.y) * frame.intrinsics.widthPx +
                                      static_cast<std::size_t>(u + frame.margin.x)]);
  return w;
}

// Whether ranges a and b (either may be the sky's infinity) are the same surface: within 3%.
bool sameRange(float a, float b) {
  if (std::isinf(a) || std::isinf(b)) return std::isinf(a) && std::isinf(b);
  return std::abs(a - b) <= 0.03f * std::min(a, b);
}

// Rows of column `u` of `a` whose range column `ub` of `b` has in none of the rows v − 1 … v + 1:
// where the two columns' horizon or terrain part by more than a pixel.
int rowsApart(const Window& a, int u, const Window& b, int ub) {
  int apart = 0;
  for (int v = 0; v < a.heightPx; ++v) {
    bool near = false;
    for (int dv = -1; dv <= 1 && !near; ++dv) {
      const int vb = v + dv;
      near = vb >= 0 && vb < b.heightPx && sameRange(a.at(u, v), b.at(ub, vb));
    }
    apart += near ? 0 : 1;
  }
  return apart;
}

// A channel 240 rows high yawed `headingDeg` on the ownship, its window's edges at tangents
// `left`, `right` (horizontal) and ±0.6 (vertical) from its axis, 200 pixels per unit of tangent:
// square pixels, and the window's pixel columns are whole steps of tangent.
constexpr int kRows = 240;
constexpr double kPxPerTangent = 200.0;
ChannelView channel(double headingDeg, double left, double right) {
  ViewConfig v;
  v.offset.headingRad = radians(headingDeg);
  v.frustum = FrustumAngles{std::atan(left), std::atan(right), std::atan(0.6), std::atan(-0.6)};
  return channelViewOf(v, static_cast<int>(std::lround(kPxPerTangent * (right - left))), kRows, radians(60.0));
}

// A flat wall of three screens side by side, as on a flight deck's front: the windows share one
// axis, and the side ones lie wholly off it (their principal point outside the image). They must
// show what one window over the three shows, pixel for pixel: the same rays.
TEST(ChannelView, ThreeOffAxisScreensOfAFlatWallShowWhatOneWideWindowShows) {
  const std::vector<ChannelView> wall{channel(0.0, -1.5, -0.5), channel(0.0, -0.5, 0.5), channel(0.0, 0.5, 1.5)};
  const Window all = render(channel(0.0, -1.5, 1.5), ownship());
  ASSERT_EQ(all.widthPx, 600);
  EXPECT_GT(wall[0].display.cxPx, wall[0].display.widthPx);  // the axis right of the left screen
  EXPECT_LT(wall[2].display.cxPx, 0.0);                      // and left of the right one
  std::vector<Window> screens;
  for (const ChannelView& v : wall) screens.push_back(render(v, ownship()));
  int pixels = 0, same = 0, terrain = 0;
  for (int k = 0; k < 3; ++k) {
    const Window& s = screens[static_cast<std::size_t>(k)];
    ASSERT_EQ(s.widthPx, 200);
    for (int v = 0; v < kRows; ++v)
      for (int u = 0; u < s.widthPx; ++u) {
        ++pixels;
        same += sameRange(s.at(u, v), all.at(200 * k + u, v)) ? 1 : 0;
        terrain += std::isfinite(s.at(u, v)) ? 1 : 0;
      }
  }
  // Along each border the screens continue as the wide window does across those two columns
  for (int border = 1; border <= 2; ++border) {
    const int acrossTheSeam =
        rowsApart(screens[static_cast<std::size_t>(border) - 1], 199, screens[static_cast<std::size_t>(border)], 0);
    const int acrossTheWide = rowsApart(all, 200 * border - 1, all, 200 * border);
    std::printf("border %d: %d rows apart across the seam, %d across the same two columns of the wide window\n", border,
                acrossTheSeam, acrossTheWide);
    EXPECT_LE(acrossTheSeam, acrossTheWide);
  }
  std::printf("%d of %d pixels see what the wide window sees there (%d on terrain)\n", same, pixels, terrain);
  EXPECT_GE(same, pixels * 999 / 1000);
  EXPECT_GT(terrain, pixels / 4);
  EXPECT_LT(terrain, pixels * 9 / 10);
}

// A cockpit's out-the-window set: three screens turned 40° from each other, each ±20° wide, edges
// abutting. Each border lies 20° off both its screens' axes, so a direction there falls on the
// same row of both: the horizon and the terrain must go on across it as across two columns of
// one screen.
TEST(ChannelView, ThreeYawedChannelsContinueAcrossTheirSeams) {
  const double edge = std::tan(radians(20.0));
  std::vector<Window> set;
  for (const double heading : {-40.0, 0.0, 40.0}) set.push_back(render(channel(heading, -edge, edge), ownship()));
  const Window& centre = set[1];
  const int last = centre.widthPx - 1;
  int terrainRows = 0;
  for (int v = 0; v < kRows; ++v) terrainRows += std::isfinite(centre.at(0, v)) ? 1 : 0;
  const int leftSeam = rowsApart(set[0], last, centre, 0), rightSeam = rowsApart(centre, last, set[2], 0);
  const int withinLeft = rowsApart(centre, 0, centre, 1), withinRight = rowsApart(centre, last - 1, centre, last);
  std::printf("rows apart across the seams %d and %d; across the centre's own first and last two columns %d and %d\n",
              leftSeam, rightSeam, withinLeft, withinRight);
  EXPECT_LE(leftSeam, withinLeft + 2);
  EXPECT_LE(rightSeam, withinRight + 2);
  EXPECT_GT(terrainRows, kRows / 4);
  EXPECT_LT(terrainRows, kRows * 9 / 10);
}

TEST(ChannelView, AStereoPairShowsAPointWithTheDisparityItsEyeSeparationPredicts) {
  ViewConfig eye;
  eye.offset.headingRad = radians(20.0);  // the head turned right on the ownship,
  eye.offset.pitchRad = radians(-20.0);   // and down: the rays of the lower half meet the hills
  eye.eyeSeparationM = 1.0;               // wide, so that disparities span pixels
  eye.convergenceM = 150.0;               // near: the windows shift by 1.7 pixels each
  eye.eye = Eye::Left;
  const ChannelView leftView = channelViewOf(eye, 480, 320, radians(50.0));
  eye.eye = Eye::Right;
  const ChannelView rightView = channelViewOf(eye, 480, 320, radians(50.0));
  const Window left = render(leftView, ownship()), right = render(rightView, ownship());
  // The eyes sit 1 m apart along the head's right axis (turned with it), level with it
  const Pose shipPose = ownship();
  const Pose leftPose = offsetPose(shipPose, leftView.offset), rightPose = offsetPose(shipPose, rightView.offset);
  EXPECT_NEAR(glm::length(rightPose.positionM - leftPose.positionM), 1.0, 1e-9);
  EXPECT_NEAR(glm::dot(rightPose.positionM - leftPose.positionM, cameraAxes(leftPose).right), 1.0, 1e-9);
  int points = 0, matched = 0, nearDepth = 0, farDepth = 0;
  double maxFormulaError = 0.0;
  for (int v = left.heightPx / 2; v < left.heightPx; v += 7) {
    for (int u = 20; u < left.widthPx - 20; u += 11) {
      const float range = left.at(u, v);
      if (!std::isfinite(range)) continue;
      // The point the left eye sees there, at depth Z in both eyes' cameras
      const glm::dvec2 pixel = pixelCentre(u, v);
      const glm::dvec3 point =
          left.pose.positionM + static_cast<double>(range) * pixelRay(left.pose, left.display, pixel);
      const double depth = worldToCamera(left.pose, point).z;
      const double disparity = left.display.fxPx * eye.eyeSeparationM * (1.0 / depth - 1.0 / eye.convergenceM);
      const glm::dvec2 predicted{pixel.x - disparity, pixel.y};
      // The configured eyes project it there (the composition of offset and window)
      const std::optional<glm::dvec2> projected = projectPoint(right.pose, right.display, point);
      ASSERT_TRUE(projected.has_value());
      maxFormulaError = std::max(maxFormulaError, glm::length(*projected - predicted));
      const int ur = static_cast<int>(std::lround(predicted.x - 0.5)), vr = v;  // the pixel it falls in
      if (ur < 0 || ur >= right.widthPx) continue;
      ++points;
      (depth < eye.convergenceM ? nearDepth : farDepth)++;
      // ... and the right eye's image shows it there: what that pixel sees, seen from the left eye,
      // lies within a pixel of where the left eye saw the point
      const float rangeRight = right.at(ur, vr);
      if (!std::isfinite(rangeRight)) continue;
      const glm::dvec3 seenRight = right.pose.positionM + static_cast<double>(rangeRight) *
                                                              pixelRay(right.pose, right.display, pixelCentre(ur, vr));
      const std::optional<glm::dvec2> back = projectPoint(left.pose, left.display, seenRight);
      const bool seen = back && std::abs(back->x - pixel.x) <= 1.0 && std::abs(back->y - pixel.y) <= 1.0;
      matched += seen ? 1 : 0;
    }
  }
  std::printf(
      "%d of %d points seen where the disparity puts them (%d nearer than the convergence, %d beyond); "
      "projection against the formula %.2e px\n",
      matched, points, nearDepth, farDepth, maxFormulaError);
  EXPECT_LT(maxFormulaError, 1e-6);
  EXPECT_GT(nearDepth, 50);
  EXPECT_GT(farDepth, 50);
  EXPECT_GE(matched, points * 97 / 100);
}

}  // namespace
}  // namespace fieldcast::app
