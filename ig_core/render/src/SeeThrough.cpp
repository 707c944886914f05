// Secondary rays through complex sticks: a walk of level-0 voxel columns as boxes near the
// objects, then the per-ray march (see SeeThrough.h).
#include "SeeThrough.h"

#include "RayMarch.h"
#include "SpanFill.h"
#include "StickShading.h"
#include "TileWindows.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <optional>

namespace fieldcast::core {

using namespace ray_march;

namespace {

// At most this many columns walked as boxes (a ray along a hedge row or under a long deck); then
// the per-ray march takes the rest.
constexpr int kMaxBoxColumns = 256;

}  // namespace

SeenThrough seeThrough(const CasterFrame& f, CasterThread& t, const glm::dvec3& d, double depthM,
                       TileWindows& window) noexcept {
  ++t.secondaryRays;
  const double length = glm::length(d);
  const float flat = f.shading.light().flat();
  const auto lit = [&](std::uint32_t rgba) { return Rgb{unpackRgb(rgba).v * flat}; };
  const auto rangeAt = [&](double depth) { return static_cast<float>(depth * length); };
  SeeThroughLayers layers;
  const auto finish = [&](const Rgb& hazed, float range) {
    const auto [colour, rangeM] = layers.finish(hazed, range);
    return SeenThrough{colour, rangeM};
  };
  const auto blend = [&](std::uint32_t rgba, double depth) {
    if ((rgba >> 24) != 0) {
      layers.add(f.shading.terrain(lit(rgba), rangeAt(depth)), static_cast<float>(rgba >> 24) / 255.0f, rangeAt(depth));
    }
  };
  const auto solid = [&](double depth, std::uint32_t rgba) {
    const float range = rangeAt(depth);
    return finish(f.shading.terrain(lit(rgba), range), range);
  };

  // The ray in grid units per metre of depth: x, y level-0 voxels (voxel i spans i − ½ … i + ½),
  // z height quanta.
  const double gx = d.x * f.unitsPerM, gy = d.y * f.unitsPerM, gz = d.z * f.quantaPerM;
  const auto heightOf = [&](int x, int y) -> double { return windowHeight(f, t, window, 0, x, y); };
  const auto zAt = [&](double s) { return f.camZq + s * gz; };
  const auto sAtZ = [&](double z) { return (z - f.camZq) / gz; };
  const int stepX = gx > 0.0 ? 1 : -1, stepY = gy > 0.0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double dsX = gx != 0.0 ? 1.0 / std::abs(gx) : inf, dsY = gy != 0.0 ? 1.0 / std::abs(gy) : inf;
  const int width = f.levelWidth[0], height = f.levelHeight[0];
  // The walk: its depth s, column (i, j), the depths of the next column boundaries, the column it
  // started in (its hit lies on the surface between voxel centres, which may dip under a box's
  // top: that box has rules of its own, below), and the stick-free columns in a row just walked.
  double s = 0.0, nextX = inf, nextY = inf;
  int i = 0, j = 0, startI = 0, startJ = 0, free = 0;
  bool restarted = false;  // the walk was started again further along (marchOn)
  const auto startAt = [&](double depth) {
    s = depth;
    i = startI = floorToInt(f.camX + s * gx + 0.5);
    j = startJ = floorToInt(f.camY + s * gy + 0.5);
    nextX = gx != 0.0 ? (i + 0.5 * stepX - f.camX) / gx : inf;
    nextY = gy != 0.0 ? (j + 0.5 * stepY - f.camY) / gy : inf;
    free = 0;
  };
  startAt(depthM);
  // The height field's surface under the ray at depth sAt, bilinear between level-0 voxel centres.
  const auto surfaceAt = [&](double sAt) {
    const double x = f.camX + sAt * gx, y = f.camY + sAt * gy;
    const int x0 = floorToInt(x), y0 = floorToInt(y);
    const double fx = x - x0, fy = y - y0;
    const double h00 = heightOf(x0, y0), h10 = heightOf(x0 + 1, y0);
    const double h01 = heightOf(x0, y0 + 1), h11 = heightOf(x0 + 1, y0 + 1);
    const double a = h00 + fx * (h10 - h00), b = h01 + fx * (h11 - h01);
    return a + fy * (b - a);
  };

  // The sky or base plane a ray that meets nothing more sees
  const auto missedAll = [&] {
    float range;
    const Rgb missed = f.missed(d.z, length, range);
    return finish(missed, range);
  };
  // The per-ray march from depth `from` on. Done: what it meets, or the sky or base plane it
  // misses to. Not done: it went back before `from` (it retraces a start under the surface, and
  // its grid line before the start can lie on the slope of an object just passed), or it met a
  // see-through texel again — then the walk goes on from there.
  RayLine line;
  int onGrid = -1;  // the ray's line set up and on the grid (1) or not (0); not yet (−1): most rays never march
  const auto marchOn = [&](double from) -> std::optional<SeenThrough> {
    if (onGrid < 0) onGrid = setupLine(f, d, line) ? 1 : 0;
    const MarchHit h = onGrid != 0 ? march(f, t, line, from * line.aMaj) : MarchHit{};
    if (!h.hit) return missedAll();
    const double depth = h.m / line.aMaj;
    if (depth < from * (1.0 - 1e-9)) return std::nullopt;
    std::uint32_t texel = 0xFF000000u;
    const Rgb colour = hitColour(f, t, line, h, depth, &texel);
    if (seeThroughTexel(texel)) {
      startAt(depth);
      restarted = true;
      return std::nullopt;
    }
    const float range = rangeAt(depth);
    return finish(f.shading.terrain(colour, range), range);
  };

  for (int walked = 0; walked < kMaxBoxColumns; ++walked) {
    if (i < 0 || j < 0 || i >= width || j >= height) {
      // Left the grid: nothing more to walk through
      if (const std::optional<SeenThrough> beyond = marchOn(s)) return *beyond;
      break;
    }
    const double sOut = std::min(nextX, nextY);
    const bool first = i == startI && j == startJ;
    const double top = heightOf(i, j);
    const StickVoxel stick = windowStick(f, t, window, 0, i, j);
    // (A coarser level's stick standing in for a missing tile is opaque: its texels are filled.)
    const bool complex = stick.id != 0 && stick.level == 0 && f.sticks->entry(stick.id).kind == StickKind::Complex;
    if (!complex) {
      // The start column does not count: the ray leaves it, it has not been clear of it
      free = stick.id != 0 ? 0 : first ? free : free + 1;
      if (free >= 2 && zAt(s) > surfaceAt(s)) {
        // Clear of the objects and above the surface: the per-ray march takes it on from here
        restarted = false;
        if (const std::optional<SeenThrough> beyond = marchOn(s)) return *beyond;
        if (restarted) continue;  // on from a see-through texel further along
      }
      // Solid below its top: entered through its side, or through its top on the way down. The
      // start column through its top from a start above it (past a stick's edge the hit lies at
      // the height of the stick's cavity over the ground beside it: the ray falls onto that
      // ground, not through it). A start inside its box (the hit lies on the surface between voxel
      // centres, which may dip under a box's top) did not enter it and passes through, unless it
      // would leave the column under that surface (steeply down on a slope; a vertical ray never
      // leaves): then it is met where it starts, not on a side metres under the ground.
      double sHit = inf;
      const bool above = zAt(s) >= top;
      if (!above && !first) {
        sHit = s;
      } else if (!above) {
        const bool leavesAbove = sOut < inf ? zAt(sOut) >= surfaceAt(sOut) : gz > 0.0;
        if (!leavesAbove) sHit = s;
      } else if (gz < 0.0 && zAt(sOut) < top) {
        sHit = std::max(s, sAtZ(top));
      }
      if (sHit < inf) {
        if (stick.id == 0) return solid(sHit, windowColour(f, t, window, 0, i, j));
        const double zHit = std::min(zAt(sHit), top);
        return solid(sHit, stickTexel(f.sticks->texels(stick.id, stick.level),
                                      stickTexelCoordinate(stick, zHit, f.stickUnitsPerQ)));
      }
    } else {
      // The column's texels in the order the ray passes them, from the one it enters by, one
      // texel boundary at a time: opaque ends it, semi-transparent is blended (each once), a
      // cavity is passed; below the stick's foot lies the ground.
      free = 0;
      const std::span<const std::uint32_t> texels = f.sticks->texels(stick.id, 0);
      const auto count = static_cast<int>(texels.size());
      const double unitsPerQ = f.stickUnitsPerQ;
      double at = s;
      if (zAt(at) >= top) {
        at = gz < 0.0 ? sAtZ(top) : inf;  // over the top: down onto it, or on over it
      }
      if (at < sOut) {
        int k = std::max(floorToInt((top - zAt(at)) * unitsPerQ), 0);
        const int step = gz < 0.0 ? 1 : gz > 0.0 ? -1 : 0;  // down the stick, up it, or level
        for (; k >= 0; k += step) {
          if (k >= count) return solid(at, windowColour(f, t, window, 0, i, j));
          const std::uint32_t texel = texels[static_cast<std::size_t>(k)];
          if (!seeThroughTexel(texel)) return solid(at, texel);
          blend(texel, at);
          if (step == 0) break;
          // Where the ray leaves texel k: its foot going down, its top going up
          at = std::max(at, sAtZ(top - (step > 0 ? k + 1 : k) / unitsPerQ));
          if (at >= sOut) break;
        }
      }
    }
    // The next column. A vertical ray has none: going down it has met its column, going up it
    // climbs clear of the terrain.
    if (sOut == inf) return missedAll();
    if (nextX < nextY) {
      s = nextX;
      nextX += dsX;
      i += stepX;
    } else {
      s = nextY;
      nextY += dsY;
      j += stepY;
    }
  }
  // Walked too far (along a hedge, under a long deck): the per-ray march from here, else the
  // ground here
  if (const std::optional<SeenThrough> beyond = marchOn(s)) return *beyond;
  return solid(s, windowColour(f, t, window, 0, std::clamp(i, 0, width - 1), std::clamp(j, 0, height - 1)));
}

SpanPixel seeThroughPixel(const SeeThroughColumn& column, int q, float rangeM) noexcept {
  const CasterFrame& f = *column.frame;
  const glm::dvec3 d = f.geo->ray(column.uc, (q + 0.5) / f.supersample);
  const SeenThrough seen = seeThrough(f, *column.thread, d, rangeM / glm::length(d), *column.window);
  return {seen.colour, seen.rangeM};
}

}  // namespace fieldcast::core
