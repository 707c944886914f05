#pragma once
// Shared helpers of the renderer tests: a small hilly terrain, poses over it, and the comparison
// of a frame's hits with the reference renderer's.
#include <ig_core/ObjectPlacement.h>
#include <ig_core/ReferenceRenderer.h>
#include <ig_core/RenderSettings.h>
#include <ig_core/SyntheticTerrain.h>
#include <ig_core/ViewGeometry.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Frame.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

namespace fieldcast::core::test {

/// RGBA8 of an opaque colour (R in the low byte).
constexpr std::uint32_t opaqueRgb(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
  return r | (g << 8) | (b << 16) | 0xFF000000u;
}

/// Pixels of RGB `frame` within `tolerance` of colour `rgba`, channel by channel.
inline int pixelsNear(const Frame& frame, std::uint32_t rgba, int tolerance) {
  int count = 0;
  for (int v = 0; v < frame.image.heightPx(); ++v) {
    const std::uint8_t* row = frame.image.row(v);
    for (int u = 0; u < frame.image.widthPx(); ++u) {
      bool near = true;
      for (int c = 0; c < 3; ++c)
        near = near && std::abs(row[3 * u + c] - static_cast<int>((rgba >> (8 * c)) & 0xFF)) <= tolerance;
      count += near ? 1 : 0;
    }
  }
  return count;
}

/// Pixels of two RGB frames of one size whose colours differ by more than `by` in some channel.
inline int pixelsDiffering(const Frame& a, const Frame& b, int by) {
  int count = 0;
  for (int v = 0; v < a.image.heightPx(); ++v)
    for (int u = 0; u < a.image.widthPx(); ++u) {
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(a.image.row(v)[3 * u + c] - b.image.row(v)[3 * u + c]));
      count += d > by ? 1 : 0;
    }
  return count;
}

/// The hills every renderer test uses: 512² voxels at 2 m, 64-voxel tiles (many tile crossings).
inline const MemoryTerrain& hills() {
  static const std::unique_ptr<MemoryTerrain> terrain = makeSyntheticTerrain({SyntheticKind::Hills, 512, 2.0, 6, 3});
  return *terrain;
}

/// The hills furnished with objects: a tree (conifer or broadleaf) on a jittered 8 m lattice over
/// half the ground, and a village of 5 × 5 houses with a church around (420, 380), the sweep's
/// point.
inline const MemoryTerrain& furnishedHills() {
  static const std::unique_ptr<MemoryTerrain> terrain = [] {
    const TerrainView& bare = hills().view();
    TerrainGrid grid;
    grid.geometry = bare.geometry();
    const int n = grid.geometry.widthVox;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        grid.heightQ.push_back(bare.heightQ(0, i, j));
        grid.colourRgba.push_back(bare.colourRgba(0, i, j));
      }
    std::vector<ObjectPlacement> objects;
    for (int j = 0; j < n / 4; ++j)
      for (int i = 0; i < n / 4; ++i) {
        const std::uint32_t h =
            (static_cast<std::uint32_t>(i) * 73856093u) ^ (static_cast<std::uint32_t>(j) * 19349663u);
        if (h % 2 == 0 || std::hypot(i * 8.0 - 420.0, j * 8.0 - 380.0) < 120.0) continue;
        objects.push_back({h % 3 == 0 ? "broadleaf" : "conifer", i * 8.0 + (h >> 8) % 5, j * 8.0 + (h >> 12) % 5,
                           static_cast<double>((h >> 4) % 360), 0.8 + 0.1 * ((h >> 16) % 5)});
      }
    for (int k = 0; k < 25; ++k) {
      objects.push_back({"house", 340.0 + 40.0 * (k % 5), 300.0 + 40.0 * (k / 5), 15.0 * k, 1.0});
    }
    objects.push_back({"church", 420.0, 380.0, 30.0, 1.0});
    placeObjects(grid, objects);
    return std::make_unique<MemoryTerrain>(grid.geometry, grid.heightQ, grid.colourRgba, grid.stickId, grid.sticks);
  }();
  return *terrain;
}

/// A pose `altitudeM` above the ground at (x, y).
inline Pose poseAbove(const TerrainView& view, double x, double y, double altitudeM, double headingDeg, double pitchDeg,
                      double rollDeg = 0.0) {
  Pose p;
  p.positionM = {x, y, view.heightAtM(x, y) + altitudeM};
  p.headingRad = radians(headingDeg);
  p.pitchRad = radians(pitchDeg);
  p.rollRad = radians(rollDeg);
  return p;
}

/// Level-`level` voxel (Chebyshev) distance between two world points' voxels.
inline int voxelDistance(const TerrainGeometry& g, const glm::dvec3& a, const glm::dvec3& b, int level) {
  const auto index = [&](double w, double origin) {
    return static_cast<int>(std::floor(std::ldexp((w - origin) / g.spacingM + 0.5, -level)));
  };
  return std::max(std::abs(index(a.x, g.originM.x) - index(b.x, g.originM.x)),
                  std::abs(index(a.y, g.originM.y) - index(b.y, g.originM.y)));
}

/// Agreement of a frame's range image with the reference's, pixel by pixel.
struct HitAgreement {
  int pixels = 0;
  int same = 0;         ///< same voxel or a neighbour at the fast frame's level, or both sky
  int skyMismatch = 0;  ///< one beyond the edge (sky or base plane), terrain in the other, away from the edge
  int atEdge = 0;       ///< one beyond the edge, terrain within a voxel of the terrain's edge in the other
  double fraction() const { return pixels ? static_cast<double>(same) / pixels : 1.0; }
};

/// How far world point `p` lies inside the hull of the level-0 voxel centres (negative: outside).
inline double insideGridM(const TerrainGeometry& g, const glm::dvec3& p) {
  return std::min({p.x - g.originM.x, g.originM.x + (g.widthVox - 1) * g.spacingM - p.x, p.y - g.originM.y,
                   g.originM.y + (g.heightVox - 1) * g.spacingM - p.y});
}

/// The pixels of a rolled frame outside its footprint repeat their columns' ends: not compared.
inline HitAgreement compareHits(const Frame& fast, const Frame& reference, const TerrainGeometry& g,
                                const RenderSettings& settings) {
  const ViewGeometry geo(fast.pose, fast.intrinsics, g, settings);
  HitAgreement a;
  const int w = fast.intrinsics.widthPx;
  for (int v = 0; v < fast.intrinsics.heightPx; ++v) {
    for (int u = 0; u < w; ++u) {
      if (!fast.footprint.whole) {
        const RowRun run = fast.footprint.rows(u);
        if (v < run.first || v >= run.end) continue;
      }
      const std::size_t k = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + u;
      const float rf = fast.rangeM[k];
      const float rr = reference.rangeM[k];
      ++a.pixels;
      const glm::dvec3 d = geo.ray(u + 0.5, v + 0.5);
      const glm::dvec3 unit = glm::normalize(d);
      if (std::isinf(rf) && std::isinf(rr)) {
        ++a.same;
        continue;
      }
      if (!std::isinf(rf) && !std::isinf(rr)) {
        const glm::dvec3 pf = fast.pose.positionM + static_cast<double>(rf) * unit;
        const glm::dvec3 pr = fast.pose.positionM + static_cast<double>(rr) * unit;
        const int level = geo.lodLevel(rf / glm::length(d), d);
        if (voxelDistance(g, pf, pr, level) <= 1) {
          ++a.same;
          continue;
        }
      }
      // One saw terrain, the other past it: the sky, or the base plane outside the grid. Where the
      // terrain ends, the caster's last sample is the last grid line of its level: a hit within
      // one voxel (at that level) of the edge counts as a neighbour.
      const double near = std::min(rf, rr);
      const double far = std::max(rf, rr);
      if (!std::isinf(far) && insideGridM(g, fast.pose.positionM + far * unit) >= 0.0) continue;  // both terrain
      const glm::dvec3 p = fast.pose.positionM + near * unit;
      const double voxel = std::ldexp(g.spacingM, geo.lodLevel(near / glm::length(d), d));
      if (std::abs(insideGridM(g, p)) <= voxel) {
        ++a.same;
        ++a.atEdge;
        continue;
      }
      ++a.skyMismatch;
      if (std::getenv("FIELDCAST_DEBUG_HITS")) {
        std::printf("  past-the-edge mismatch at (%d,%d): fast %s, hit at %.1f %.1f %.1f\n", u, v,
                    rf > rr ? "past" : "hit", p.x, p.y, p.z);
      }
    }
  }
  return a;
}

}  // namespace fieldcast::core::test
