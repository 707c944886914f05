#pragma once
// The render benchmarks' views: four poses over the terrain's centre (looking down, oblique, low,
// and at the horizon) at two display sizes, shared by fieldcast_bench_render and
// fieldcast_bench_table so that both time the same frames.

#include <ig_core/Renderer.h>
#include <ig_core/TerrainView.h>

#include <fieldcast/Conventions.h>

#include <array>

namespace fieldcast::core {

struct BenchPose {
  const char* name;
  double headingDeg, pitchDeg, altitudeM;
  bool nearHorizon;  ///< pitched little enough that a shear stands in for the pitch (VoxelSpace)
};
inline constexpr std::array<BenchPose, 4> kPoses{{
    {"down", 30.0, -70.0, 400.0, false},
    {"oblique", 75.0, -25.0, 250.0, false},
    {"low", 200.0, -8.0, 60.0, true},
    {"horizon", 315.0, -1.0, 30.0, true},
}};
inline constexpr std::array<std::array<int, 2>, 2> kSizes{{{720, 486}, {1920, 1080}}};

/// Pose `pose` of kPoses over the centre of `view`'s terrain, displayed at kSizes[size] with a
/// horizontal field of view of 60°.
inline ViewRequest benchRequest(const TerrainView& view, int pose, int size) {
  const BenchPose& p = kPoses[static_cast<std::size_t>(pose)];
  const TerrainGeometry& g = view.geometry();
  const double x = g.originM.x + 0.5 * (g.widthVox - 1) * g.spacingM;
  const double y = g.originM.y + 0.5 * (g.heightVox - 1) * g.spacingM;
  ViewRequest r;
  r.pose.positionM = {x, y, view.heightAtM(x, y) + p.altitudeM};
  r.pose.headingRad = radians(p.headingDeg);
  r.pose.pitchRad = radians(p.pitchDeg);
  const auto& s = kSizes[static_cast<std::size_t>(size)];
  r.display = Intrinsics::fromHorizontalFov(s[0], s[1], radians(60.0));
  return r;
}

}  // namespace fieldcast::core
