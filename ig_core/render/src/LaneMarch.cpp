// The lane march (LaneMarch.h): the column-plane march of PlaneMarch.cpp for neighbouring columns
// in step, one grid line after another.
#include "LaneMarch.h"

#include "CrossingFill.h"
#include "RayMarch.h"
#include "TileWindows.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <tuple>
#include <utility>

namespace fieldcast::core::plane_march {

using ray_march::ceilToInt;
using ray_march::floorToInt;
using ray_march::levelIndex;
using ray_march::pow2;

namespace {

constexpr int kNoGuess = std::numeric_limits<int>::min();

// The grid line the block is on, and what the lanes share there: the camera's axes and position
// are the same for every column, so a point's camera coordinates (yc, zc) are too.
struct BlockLine {
  int sx = 1;
  int level = 0;
  int i = 0;
  double p = 1;                   // 2^level
  double dMaj = 0;                // the line's major offset from the camera, level-0 units
  double minOffset = 0;           // minor offset from the camera of segment 0's start
  double yLine = 0, zLine = 0;    // camera yc, zc of minor position 0 at height 0 on the line
  double yStep = 0, zStep = 0;    // their change per line
  double yMinor = 0, zMinor = 0;  // per level-L minor unit
  double switchDepth = 0;         // past this depth (stretched) a column's march takes the next level
  double minorLinesDepth = 0;     // nearer, fills are split at the minor axis's lines (PlaneMarch.cpp)
  int majLast = 0, minLast = 0;   // the level's last line inside the grid, last minor segment
};

// One column marched in a lane: its plane's terms on the block's line and its march's state.
struct Lane {
  enum class State { Waiting, Marching, Done };
  State state = State::Done;
  LaneColumn* column = nullptr;
  const ColumnPlane* c = nullptr;
  ColumnFill fill{};
  int joinLine = 0;                     // the line (block level) the column's march starts on
  double gA = 0, baseStep = 0, base = 0;  // g(minor, h) = gA·minor + nZ·h + base on the line
  double drift = 0;                     // minor change of the plane's trace per line
  double jPos = 0;                      // predicted minor position of the next crossing
  int jGuess = kNoGuess;                // its segment, when the last solve found it
  int q = 0;                            // the next sub-row to fill
  double vq = 0, rowSlope = 0;          // its centre, and yc / zc of its ray
  double stretch = 1, switchZc = 0;     // the grazing-angle stretch of its ray, the switch depth over it
  double rayZPerDMaj = 0;               // the next sub-row's ray: its height gain per unit of dMaj
  bool rayClimbs = false;               // ... and whether it climbs (along the march)
  bool lastFilledNothing = false;
  int prev = 0;  // crossings[prev] is the last crossing solved
  Crossing crossings[2]{};
  std::uint64_t steps = 0;
};

}  // namespace

namespace {

template <bool kXMajor, bool kSticks>
void marchLanesAxis(const CasterFrame& f, CasterThread& t, std::span<LaneColumn> columns, TileWindows& window) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const CameraAxes& axes = f.geo->axes();
  const ColumnPlane& c0 = *columns.front().plane;  // the camera's terms: the same in every plane
  const double invS = 1.0 / columns.front().sink->s;
  const double invFy = 1.0 / k.fyPx;
  const double cMinHalf = 0.5 + c0.cMin;
  const auto& majSizes = kXMajor ? f.levelWidth : f.levelHeight;
  const auto& minSizes = kXMajor ? f.levelHeight : f.levelWidth;
  const double minorLinesDepth0 = k.fxPx / (f.unitsPerM * kMinorLinesVoxelPx);
  const bool grazingLod = f.geo->grazingLod();
  const auto height = [&](int lv, int i, int j) __attribute__((always_inline))->double {
    return kXMajor ? windowHeight(f, t, window, lv, i, j) : windowHeight(f, t, window, lv, j, i);
  };

  BlockLine b;
  b.sx = c0.sx;
  const int sx = b.sx;
  const int evenParity = sx > 0 ? 0 : 1;  // lines where the coarser level's line lies half a step ahead
  const auto enterLevel = [&](int lv) {
    b.level = lv;
    b.p = pow2(lv);
    b.minOffset = 0.5 * b.p - cMinHalf;
    b.yMinor = c0.upMin * b.p;
    b.zMinor = c0.fwdMin * b.p;
    b.yStep = c0.upMaj * sx * b.p;
    b.zStep = c0.fwdMaj * sx * b.p;
    b.switchDepth = lv + 1 < f.levels ? f.geo->lodDepth0M() * b.p : std::numeric_limits<double>::infinity();
    b.minorLinesDepth = minorLinesDepth0 * b.p;
    const int hullLast = sx > 0 ? floorToInt(levelIndex(c0.majSize - 1, lv)) : ceilToInt(levelIndex(0.0, lv));
    b.majLast = sx > 0 ? std::min(hullLast, majSizes[static_cast<std::size_t>(lv)] - 1) : std::max(hullLast, 0);
    b.minLast = minSizes[static_cast<std::size_t>(lv)] - 2;
  };
  const auto setLine = [&](int line) {
    b.i = line;
    b.dMaj = (line + 0.5) * b.p - 0.5 - c0.cMaj;
    b.yLine = b.dMaj * c0.upMaj + b.minOffset * c0.upMin - c0.cZ * c0.upZ;
    b.zLine = b.dMaj * c0.fwdMaj + b.minOffset * c0.fwdMin - c0.cZ * c0.fwdZ;
  };
  // A lane's plane on the block's line (after a level change or a join)
  const auto setLaneLine = [&](Lane& lane) {
    const ColumnPlane& c = *lane.c;
    lane.gA = c.nMin * b.p;
    lane.baseStep = c.nMaj * sx * b.p;
    lane.base = c.nMaj * b.dMaj + c.nMin * b.minOffset - c.nZ * c.cZ;
    lane.switchZc = b.switchDepth / lane.stretch;
  };
  const auto joinLineOf = [&](const LaneColumn& column) {
    const double startMaj = kXMajor ? column.start.x : column.start.y;
    return sx > 0 ? floorToInt(levelIndex(startMaj, b.level)) : ceilToInt(levelIndex(startMaj, b.level));
  };
  const auto stretchOfRow = [&](const ColumnPlane& c, int row) {
    const double yc = (k.cyPx - (row + 0.5) * invS) / k.fyPx;
    return f.geo->lodStretch(c.xc * axes.right + yc * axes.up + axes.forward);
  };
  // The next sub-row's ray of a lane, for the test whether it passes over all the terrain
  const auto aimRowRay = [&](Lane& lane) {
    const ColumnPlane& c = *lane.c;
    lane.rowSlope = (k.cyPx - lane.vq) * invFy;
    const double rMaj = c.aMaj + lane.rowSlope * c.bMaj;
    const double rZ = c.aZ + lane.rowSlope * c.bZ;
    lane.rayClimbs = rMaj * sx > 1e-12 && rZ >= 0.0;
    lane.rayZPerDMaj = lane.rayClimbs ? rZ / rMaj : 0.0;
  };

  // Solves a lane's crossing on the block's line into `out`; false when it leaves the grid or the view.
  const auto solve = [&](Lane& lane, Crossing& out) __attribute__((always_inline))->bool {
    const int i = b.i;
    if (sx > 0 ? i > b.majLast : i < b.majLast) return false;
    if (b.minLast < 0) return false;
    const double nZ = lane.c->nZ;
    int j = lane.jGuess != kNoGuess ? lane.jGuess : floorToInt(lane.jPos);
    j = j < 0 ? 0 : (j > b.minLast ? b.minLast : j);
    double h0 = height(b.level, i, j);
    double h1 = height(b.level, i, j + 1);
    double g0 = lane.gA * j + nZ * h0 + lane.base;
    double g1 = g0 + lane.gA + nZ * (h1 - h0);
    std::uint64_t samples = 2;
    // g grows along the minor axis: walk to the segment where it changes sign.
    while (g0 > 0.0) {
      if (j == 0) return false;
      --j;
      h1 = h0;
      g1 = g0;
      h0 = height(b.level, i, j);
      g0 -= lane.gA + nZ * (h1 - h0);
      ++samples;
    }
    while (g1 <= 0.0) {
      if (j == b.minLast) return false;
      ++j;
      h0 = h1;
      g0 = g1;
      h1 = height(b.level, i, j + 1);
      g1 = g0 + lane.gA + nZ * (h1 - h0);
      ++samples;
    }
    lane.steps += samples;
    const double phi = g0 / (g0 - g1);
    const double minor = j + phi;
    const double h = h0 + phi * (h1 - h0);
    const double zc = b.zLine + minor * b.zMinor + h * c0.fwdZ;
    if (!(zc > 1e-6)) return false;
    out.yc = b.yLine + minor * b.yMinor + h * c0.upZ;
    out.depth = zc;
    out.lodDepth = zc * lane.stretch;
    out.phi = phi;
    out.level = b.level;
    out.i = i;
    out.j = j;
    out.onMinorLine = false;
    out.haveColour = false;
    out.heightQ = h;
    out.haveStick = false;
    lane.jPos = minor + lane.drift;
    lane.jGuess = nextSegment(j, g0, g1, lane.drift);
    return true;
  };
  // Ends a lane's march: q, and its last crossing as where it stopped (none when `last` is null).
  const auto end = [&](Lane& lane, const Crossing* last, bool overTerrain) {
    lane.state = Lane::State::Done;
    LaneColumn& column = *lane.column;
    column.q = lane.q;
    if (last != nullptr) {
      const double lp = pow2(last->level);
      const double maj = (last->i + 0.5) * lp - 0.5;
      const double min = (last->j + 0.5 + last->phi) * lp - 0.5;
      column.stopped = PlaneStop{true, kXMajor, kXMajor ? glm::dvec2{maj, min} : glm::dvec2{min, maj}, overTerrain};
    }
    t.steps += lane.steps;
  };
  // Fills a lane's sub-rows between two crossings; true when its column is full.
  const auto fillBetween = [&](Lane& lane, Crossing& from, Crossing& to) __attribute__((always_inline))->bool {
    const int qFirst = lane.q;
    fillCrossings<kSticks>(f, t, window, *lane.c, *lane.column->sink, lane.fill, from, to, lane.q, lane.vq);
    aimRowRay(lane);
    if (grazingLod) {
      lane.stretch = stretchOfRow(*lane.c, lane.q);
      lane.switchZc = b.switchDepth / lane.stretch;
    }
    t.rays += static_cast<std::uint64_t>(qFirst - lane.q);
    return lane.q < 0;
  };

  // The lanes, and the level they start at: the finest of their bottom rays' hits
  std::array<Lane, kLaneColumns> lanes;
  const int count = std::min(static_cast<int>(columns.size()), kLaneColumns);
  int level = std::numeric_limits<int>::max();
  for (int n = 0; n < count; ++n) level = std::min(level, columns[static_cast<std::size_t>(n)].level);
  enterLevel(level);
  for (int n = 0; n < count; ++n) {
    Lane& lane = lanes[static_cast<std::size_t>(n)];
    LaneColumn& column = columns[static_cast<std::size_t>(n)];
    lane.column = &column;
    lane.c = column.plane;
    lane.state = Lane::State::Waiting;
    lane.q = column.q;
    lane.vq = (column.q + 0.5) * invS;
    lane.fill = ColumnFill{f.shading.pixelShader(),
                           static_cast<float>(invS),
                           static_cast<float>(k.cyPx),
                           static_cast<float>(1.0 / k.fyPx),
                           static_cast<float>(1.0 + lane.c->xc * lane.c->xc),
                           invS};
    lane.drift = -lane.c->nMaj / lane.c->nMin * sx;
    lane.stretch = grazingLod ? stretchOfRow(*lane.c, lane.q) : 1.0;
    lane.joinLine = joinLineOf(column);
    aimRowRay(lane);
  }
  // A lane joins on its line: its first crossing there, as its own march would start
  const auto join = [&](Lane& lane) {
    const LaneColumn& column = *lane.column;
    setLaneLine(lane);
    lane.jPos = levelIndex(kXMajor ? column.start.y : column.start.x, b.level);
    lane.jGuess = kNoGuess;
    lane.prev = 0;
    Crossing& first = lane.crossings[0];
    // The first crossing lies above the next sub-row's ray (the bottom ray hit the grid's side
    // wall, seen from outside the grid): the per-ray march takes over, as from marchPlane
    if (!solve(lane, first) || first.yc > lane.rowSlope * first.depth) {
      end(lane, nullptr, false);
      return;
    }
    lane.state = Lane::State::Marching;
  };

  // The block starts on the nearest lane's line
  const auto nearestWaiting = [&]() {
    int line = 0;
    bool any = false;
    for (int n = 0; n < count; ++n) {
      const Lane& lane = lanes[static_cast<std::size_t>(n)];
      if (lane.state != Lane::State::Waiting) continue;
      if (!any || (lane.joinLine - line) * sx < 0) line = lane.joinLine;
      any = true;
    }
    return std::pair{any, line};
  };
  Crossing onMinor[2];
  for (auto [any, line] = nearestWaiting(); any;) {
    setLine(line);
    for (;;) {
      bool marching = false, switchable = (b.i & 1) == evenParity;
      for (int n = 0; n < count; ++n) {
        Lane& lane = lanes[static_cast<std::size_t>(n)];
        if (lane.state == Lane::State::Waiting && (b.i - lane.joinLine) * sx >= 0) join(lane);
        if (lane.state == Lane::State::Marching) {
          marching = true;
          switchable = switchable && lane.crossings[lane.prev].depth > lane.switchZc;
        } else if (lane.state == Lane::State::Waiting) {
          // Not while a waiting column's start is near: the coarser line half a step ahead might pass it
          switchable = switchable && (lane.joinLine - b.i) * sx >= 2;
        }
      }
      if (!marching) break;  // the next waiting lane's line, if any
      if (switchable) {
        // Every column's march is past its switch depth: the coarser level's line, half a step ahead
        enterLevel(b.level + 1);
        setLine(b.i >> 1);
        for (int n = 0; n < count; ++n) {
          Lane& lane = lanes[static_cast<std::size_t>(n)];
          if (lane.state == Lane::State::Waiting) lane.joinLine = joinLineOf(*lane.column);
          if (lane.state != Lane::State::Marching) continue;
          setLaneLine(lane);
          lane.jPos = (lane.jPos + 0.5) * 0.5 - 0.5;
          lane.jGuess = kNoGuess;
        }
      } else {
        b.i += sx;
        b.dMaj += sx * b.p;
        b.yLine += b.yStep;
        b.zLine += b.zStep;
        for (int n = 0; n < count; ++n) lanes[static_cast<std::size_t>(n)].base += lanes[static_cast<std::size_t>(n)].baseStep;
      }
      for (int n = 0; n < count; ++n) {
        Lane& lane = lanes[static_cast<std::size_t>(n)];
        if (lane.state != Lane::State::Marching) continue;
        Crossing& prev = lane.crossings[lane.prev];
        Crossing& cur = lane.crossings[1 - lane.prev];
        if (!solve(lane, cur)) {
          end(lane, &prev, false);
          continue;
        }
        // Rows to fill: the next sub-row's ray passes below this crossing
        const bool fills = cur.yc > lane.rowSlope * cur.depth;
        lane.lastFilledNothing = !fills;
        if (fills) {
          // The crossings of the minor axis's lines in between bound the fill too (PlaneMarch.cpp)
          int minorCrossings = 0;
          if (cur.depth < b.minorLinesDepth && prev.level == b.level && prev.i == b.i - sx) {
            const MarchLine on{b.level,  b.i,       sx,     lane.gA,   lane.c->nZ, lane.base, lane.baseStep, b.yLine,
                               b.yStep,  b.zLine,   b.zStep, b.yMinor, b.zMinor,   c0.upZ,    c0.fwdZ,       lane.stretch};
            minorCrossings = solveMinorLines(on, height, prev, cur, onMinor, lane.steps);
          }
          Crossing* from = &prev;
          bool full = false;
          for (int m = 0; m < minorCrossings && !full; ++m) {
            Crossing& mid = onMinor[m];
            if (mid.yc > lane.rowSlope * mid.depth && fillBetween(lane, *from, mid)) {
              end(lane, &mid, false);
              full = true;
            }
            from = &mid;
          }
          if (full) continue;
          if (cur.yc > lane.rowSlope * cur.depth) {
            if (fillBetween(lane, *from, cur)) {
              end(lane, &cur, false);
              continue;
            }
          } else {
            lane.lastFilledNothing = true;  // a crossing of a minor line hides it
          }
        }
        lane.prev = 1 - lane.prev;
        // A row ray above all the terrain and climbing meets nothing more: the rows left see the sky
        if (lane.lastFilledNothing && lane.rayClimbs && c0.cZ + b.dMaj * lane.rayZPerDMaj > f.ceilingQ) {
          end(lane, &cur, true);
        }
      }
    }
    std::tie(any, line) = nearestWaiting();
  }
}

}  // namespace

void marchLanes(const CasterFrame& f, CasterThread& t, std::span<LaneColumn> columns, TileWindows& window) noexcept {
  if (columns.empty()) return;
  const bool xMajor = columns.front().plane->xMajor;
  if (f.sticks != nullptr) {
    xMajor ? marchLanesAxis<true, true>(f, t, columns, window) : marchLanesAxis<false, true>(f, t, columns, window);
  } else {
    xMajor ? marchLanesAxis<true, false>(f, t, columns, window) : marchLanesAxis<false, false>(f, t, columns, window);
  }
}

}  // namespace fieldcast::core::plane_march
