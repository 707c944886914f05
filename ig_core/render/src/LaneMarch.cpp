// The lane march (LaneMarch.h): the column-plane march of PlaneMarch.cpp for neighbouring columns
// in step, one grid line after another. Per line, every lane's crossing, fill test, sky test and
// next guess come from one call of the line kernel (LaneLine.h, in SIMD lanes); only the lanes
// where something happens — a crossing that fills rows, a guess that missed the crossing's
// segment, a march that ends — are taken one by one.
#include "LaneMarch.h"

#include "CrossingFill.h"
#include "LaneLine.h"
#include "RayMarch.h"
#include "TileWindows.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>
#include <utility>

namespace fieldcast::core::plane_march {

using ray_march::ceilToInt;
using ray_march::floorToInt;
using ray_march::levelIndex;
using ray_march::pow2;

static_assert(kLineLanes == kLaneColumns);

namespace {

// Eight of the line kernel's flags (bytes 0 or 1) as the bits of a byte: flag k in bit k (each
// product term is a distinct power of two, so nothing carries into the top byte but the flags).
static_assert(std::endian::native == std::endian::little, "flagBits reads the flags' bytes little-endian");
static_assert(kLaneColumns % 8 == 0 && kLaneColumns <= 32, "lanes go eight to a word, into an unsigned mask");
inline unsigned flagBits(const std::uint8_t* flags) noexcept {
  std::uint64_t bytes;
  std::memcpy(&bytes, flags, 8);
  return static_cast<unsigned>((bytes * 0x0102040810204080ull) >> 56);
}

// The bits set in an 8-bit mask. (std::popcount is a library call on the baseline SSE2 target,
// which has no popcnt instruction: 1.4% of an HD horizon frame's profile samples.)
constexpr unsigned bitsSet8(unsigned x) noexcept {
  x -= (x >> 1) & 0x55u;
  x = (x & 0x33u) + ((x >> 2) & 0x33u);
  return (x + (x >> 4)) & 0x0Fu;
}
static_assert(bitsSet8(0) == 0 && bitsSet8(0xFF) == 8 && bitsSet8(0xA5) == 4 && bitsSet8(0x80) == 1);

// The grid line the block is on, and what the lanes share there: the camera's axes and position
// are the same for every column, so a point's camera coordinates (yc, zc) are too.
struct BlockLine {
  int level = 0;
  int i = 0;
  std::int64_t count = 0;         // lines taken so far (a line's number, across level switches)
  double p = 1;                   // 2^level
  double dMaj = 0;                // the line's major offset from the camera, level-0 units
  double minOffset = 0;           // minor offset from the camera of segment 0's start
  double yLine = 0, zLine = 0;    // camera yc, zc of minor position 0 at height 0 on the line
  double yStep = 0, zStep = 0;    // their change per line
  double yMinor = 0, zMinor = 0;  // per level-L minor unit
  double switchDepth = 0;         // past this depth (stretched) a column's march takes the next level
  double minorLinesDepth = 0;     // nearer, fills are split at the minor axis's lines (PlaneMarch.cpp)
  double lookPastLinesDepth = 0;  // nearer, a voxel spans f.lookPastVoxelPx pixels or more
  int majLast = 0, minLast = 0;   // the level's last line inside the grid, last minor segment
};

// One column marched in a lane: what is its own (the line's terms are in the block's LaneLine).
struct Lane {
  int index = 0;  // its lane
  LaneColumn* column = nullptr;
  const ColumnPlane* c = nullptr;
  ColumnFill fill{};
  int joinLine = 0;                  // the line (block level) the column's march starts on
  int q = 0;                         // the next sub-row to fill
  double vq = 0;                     // its centre
  double stretch = 1, switchZc = 0;  // the grazing-angle stretch of its ray, the switch depth over it
  // Crossings made whole for a fill: slots[lastSlot], with its colour and stick once looked up, is
  // the last crossing when it bounded a fill on line lastLine (a crossing bounds the next fill
  // too); otherwise the state's arrays hold the last crossing
  Crossing slots[2]{};
  int lastSlot = 0;
  std::int64_t lastLine = -1;
  std::uint64_t steps = 0;
};

// The lanes' last crossings (structure of arrays, as the line kernel gives them) and march state.
struct LaneState {
  alignas(64) double yc[kLaneColumns]{}, depth[kLaneColumns]{}, phi[kLaneColumns]{}, heightQ[kLaneColumns]{};
  alignas(64) int j[kLaneColumns]{};
  alignas(64) double jPos[kLaneColumns]{};
  alignas(64) int jGuess[kLaneColumns]{};
  alignas(64) double baseStep[kLaneColumns]{};
  int level = 0, i = 0;  // the last crossings' line (they are all on the block's last line)
};

template <bool kXMajor, bool kSticks>
void marchLanesAxis(const CasterFrame& f, CasterThread& t, std::span<LaneColumn> columns,
                    TileWindows& window) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const CameraAxes& axes = f.geo->axes();
  const ColumnPlane& c0 = *columns.front().plane;  // the camera's terms: the same in every plane
  const double invS = 1.0 / columns.front().sink->s;
  const double invFy = 1.0 / k.fyPx;
  const double cMinHalf = 0.5 + c0.cMin;
  const auto& majSizes = kXMajor ? f.levelWidth : f.levelHeight;
  const auto& minSizes = kXMajor ? f.levelHeight : f.levelWidth;
  const double minorLinesDepth0 = k.fxPx / (f.unitsPerM * kMinorLinesVoxelPx);
  const double lookPastLinesDepth0 = k.fxPx / (f.unitsPerM * f.lookPastVoxelPx);
  const bool grazingLod = f.geo->grazingLod();
  const int sx = c0.sx;
  const int evenParity = sx > 0 ? 0 : 1;  // lines where the coarser level's line lies half a step ahead

  // The tile of the current level the heights come from, kept in registers
  HeightWindow heights(f);
  const auto height = [&](int lv, int i, int j) __attribute__((always_inline))->double {
    return kXMajor ? heights.read(f, t, window, lv, i, j) : heights.read(f, t, window, lv, j, i);
  };

  BlockLine b;
  LaneLine line{};
  LaneState s;
  unsigned waiting = 0, marchingLanes = 0;  // bit n: lane n is waiting for its line, is marching
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
    b.lookPastLinesDepth = lookPastLinesDepth0 * b.p;
    const int hullLast = sx > 0 ? floorToInt(levelIndex(c0.majSize - 1, lv)) : ceilToInt(levelIndex(0.0, lv));
    b.majLast = sx > 0 ? std::min(hullLast, majSizes[static_cast<std::size_t>(lv)] - 1) : std::max(hullLast, 0);
    b.minLast = minSizes[static_cast<std::size_t>(lv)] - 2;
    heights.reset();  // the register window belongs to the old level
  };
  const auto setLine = [&](int i) {
    b.i = i;
    b.dMaj = (i + 0.5) * b.p - 0.5 - c0.cMaj;
    b.yLine = b.dMaj * c0.upMaj + b.minOffset * c0.upMin - c0.cZ * c0.upZ;
    b.zLine = b.dMaj * c0.fwdMaj + b.minOffset * c0.fwdMin - c0.cZ * c0.fwdZ;
  };
  // A lane's plane on the block's line (after a level change or a join)
  const auto setLaneLine = [&](int n, Lane& lane) {
    const ColumnPlane& c = *lane.c;
    line.gA[n] = c.nMin * b.p;
    s.baseStep[n] = c.nMaj * sx * b.p;
    line.base[n] = c.nMaj * b.dMaj + c.nMin * b.minOffset - c.nZ * c.cZ;
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
  // A lane's next sub-row's ray: its slope, and what the kernel's test whether it passes over all
  // the terrain needs
  const auto aimRowRay = [&](int n, const Lane& lane) {
    const ColumnPlane& c = *lane.c;
    const double rowSlope = (k.cyPx - lane.vq) * invFy;
    line.rowSlope[n] = rowSlope;
    const double rMaj = c.aMaj + rowSlope * c.bMaj;
    const double rZ = c.aZ + rowSlope * c.bZ;
    const double rMin = c.aMin + rowSlope * c.bMin;
    // (Along the march, as the one-column march's row ray must be: not near the nadir)
    const bool climbs = rMaj * sx > 1e-12 && rMaj * sx > 1e-4 * std::abs(rMin) && rZ >= 0.0;
    line.rayClimbs[n] = climbs ? 1.0 : 0.0;
    line.rayZPerDMaj[n] = climbs ? rZ / rMaj : 0.0;
  };
  // Lane n's crossing on the block's line, walking from the kernel's segment (line.j, h0, h1) to
  // where g changes sign, as the one-column march's solve does; false when it leaves the grid or
  // the view. Records the crossing's values in the line's outputs, as the kernel would.
  const auto solveWalking = [&](int n, Lane& lane) -> bool {
    const int i = b.i;
    int j = line.j[n];
    double h0 = line.h0[n], h1 = line.h1[n];
    const double gA = line.gA[n], nZ = line.nZ[n];
    double g0 = gA * j + nZ * h0 + line.base[n];
    double g1 = g0 + gA + nZ * (h1 - h0);
    std::uint64_t samples = 2;
    const auto heightAt = [&](int at) { return height(b.level, i, at); };
    if (!walkToCrossing(j, h0, h1, g0, g1, gA, nZ, b.minLast, heightAt, samples)) return false;
    lane.steps += samples;
    const double phi = g0 / (g0 - g1);
    const double minor = j + phi;
    const double h = h0 + phi * (h1 - h0);
    const double zc = b.zLine + minor * b.zMinor + h * c0.fwdZ;
    if (!(zc > 1e-6)) return false;
    line.yc[n] = b.yLine + minor * b.yMinor + h * c0.upZ;
    line.depth[n] = zc;
    line.phi[n] = phi;
    line.heightQ[n] = h;
    line.j[n] = j;
    line.jPos[n] = minor + line.drift[n];
    line.jNext[n] = nextSegment(j, g0, g1, line.drift[n]);
    return true;
  };
  // Lane n's crossing on the current line (from the line's outputs) and its last one (the lane's
  // slot, or from the state's arrays), made whole in the lane's slots
  const auto setCrossing = [&](Crossing& x, int n, const double* yc, const double* depth, const double* phi,
                               const double* heightQ, const int* j, int level, int i, const Lane& lane) {
    x.yc = yc[n];
    x.depth = depth[n];
    x.lodDepth = depth[n] * lane.stretch;
    x.phi = phi[n];
    x.heightQ = heightQ[n];
    x.level = level;
    x.i = i;
    x.j = j[n];
    x.onMinorLine = false;
    x.haveColour = false;
    x.haveStick = false;
  };
  const auto lastCrossing = [&](int n, Lane& lane) -> Crossing& {
    Crossing& last = lane.slots[lane.lastSlot];
    if (lane.lastLine != b.count - 1) {
      setCrossing(last, n, s.yc, s.depth, s.phi, s.heightQ, s.j, s.level, s.i, lane);
    }
    return last;
  };
  const auto currentCrossing = [&](int n, Lane& lane) -> Crossing& {
    Crossing& cur = lane.slots[1 - lane.lastSlot];
    setCrossing(cur, n, line.yc, line.depth, line.phi, line.heightQ, line.j, b.level, b.i, lane);
    return cur;
  };
  // Ends a lane's march: q, and a crossing as where it stopped (none when `last` is null).
  const auto end = [&](Lane& lane, const Crossing* last, bool overTerrain) {
    waiting &= ~(1u << lane.index);
    marchingLanes &= ~(1u << lane.index);
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
  // Fills lane n's sub-rows between two crossings; true when its column is full.
  const auto fillBetween = [&](int n, Lane& lane, Crossing& from, Crossing& to) __attribute__((always_inline))->bool {
    const int qFirst = lane.q;
    fillCrossings<kSticks>(f, t, window, *lane.c, *lane.column->sink, lane.fill, from, to, lane.q, lane.vq);
    aimRowRay(n, lane);
    if (grazingLod) {
      lane.stretch = stretchOfRow(*lane.c, lane.q);
      lane.switchZc = b.switchDepth / lane.stretch;
    }
    t.rays += static_cast<std::uint64_t>(qFirst - lane.q);
    return lane.q < lane.fill.qTop;
  };
  // Keeps the line's crossings as the lanes' last ones, and their next guesses
  const auto keepLine = [&]() {
    std::copy_n(line.yc, kLaneColumns, s.yc);
    std::copy_n(line.depth, kLaneColumns, s.depth);
    std::copy_n(line.phi, kLaneColumns, s.phi);
    std::copy_n(line.heightQ, kLaneColumns, s.heightQ);
    std::copy_n(line.j, kLaneColumns, s.j);
    std::copy_n(line.jPos, kLaneColumns, s.jPos);
    std::copy_n(line.jNext, kLaneColumns, s.jGuess);
    s.level = b.level;
    s.i = b.i;
  };
  // Reads the heights of each marching lane's guessed segment on the block's line: straight from
  // the register window's tile when every lane's pair lies in it (neighbouring columns cross a line
  // a few voxels apart), else each through the window cache
  const auto readGuesses = [&](unsigned marching) __attribute__((always_inline)) {
    int jMin = std::numeric_limits<int>::max(), jMax = std::numeric_limits<int>::min();
    for (unsigned m = marching; m != 0; m &= m - 1) {
      const int n = std::countr_zero(m);
      int j = s.jGuess[n];
      j = j < 0 ? 0 : (j > b.minLast ? b.minLast : j);
      line.j[n] = j;
      jMin = std::min(jMin, j);
      jMax = std::max(jMax, j);
    }
    // The pairs' voxels (line i; minor jMin .. jMax + 1) in the window's tile?
    const int xLo = kXMajor ? b.i : jMin, xHi = kXMajor ? b.i : jMax + 1;
    const int yLo = kXMajor ? jMin : b.i, yHi = kXMajor ? jMax + 1 : b.i;
    if (heights.heights != nullptr && heights.holds(xLo, yLo) && heights.holds(xHi, yHi)) {
      // Voxel (line i, minor j) at lineStart + j · minorStride in the tile
      const std::ptrdiff_t minorStride = kXMajor ? std::ptrdiff_t{1} << f.tileShift : 1;
      const std::ptrdiff_t lineStart = kXMajor ? heights.index(b.i, 0) : heights.index(0, b.i);
      for (unsigned m = marching; m != 0; m &= m - 1) {
        const int n = std::countr_zero(m);
        const std::ptrdiff_t at = lineStart + line.j[n] * minorStride;
        line.h0[n] = heights.heights[at];
        line.h1[n] = heights.heights[at + minorStride];
      }
      return;
    }
    for (unsigned m = marching; m != 0; m &= m - 1) {
      const int n = std::countr_zero(m);
      line.h0[n] = height(b.level, b.i, line.j[n]);
      line.h1[n] = height(b.level, b.i, line.j[n] + 1);
    }
  };
  // The lanes, and the level they start at: the finest of their bottom rays' hits
  std::array<Lane, kLaneColumns> lanes;
  const int count = std::min(static_cast<int>(columns.size()), kLaneColumns);
  int level = std::numeric_limits<int>::max();
  for (int n = 0; n < count; ++n) level = std::min(level, columns[static_cast<std::size_t>(n)].level);
  enterLevel(level);
  line.ceilingQ = f.ceilingQ;
  line.rayZAtLine = c0.cZ;
  line.upZ = c0.upZ;
  line.fwdZ = c0.fwdZ;
  for (int n = 0; n < count; ++n) {
    Lane& lane = lanes[static_cast<std::size_t>(n)];
    LaneColumn& column = columns[static_cast<std::size_t>(n)];
    lane.index = n;
    lane.column = &column;
    lane.c = column.plane;
    waiting |= 1u << n;
    lane.q = column.q;
    lane.vq = (column.q + 0.5) * invS;
    lane.fill = ColumnFill{f.shading.pixelShader(),
                           static_cast<float>(invS),
                           static_cast<float>(k.cyPx),
                           static_cast<float>(1.0 / k.fyPx),
                           static_cast<float>(1.0 + lane.c->xc * lane.c->xc),
                           invS,
                           column.sink->qTop};
    line.nZ[n] = lane.c->nZ;
    line.drift[n] = -lane.c->nMaj / lane.c->nMin * sx;
    lane.stretch = grazingLod ? stretchOfRow(*lane.c, lane.q) : 1.0;
    lane.joinLine = joinLineOf(column);
    aimRowRay(n, lane);
  }
  // A lane joins on its line: its first crossing there, as its own march would start
  const auto join = [&](int n, Lane& lane) {
    const LaneColumn& column = *lane.column;
    setLaneLine(n, lane);
    int j = floorToInt(levelIndex(kXMajor ? column.start.y : column.start.x, b.level));
    j = j < 0 ? 0 : (j > b.minLast ? b.minLast : j);
    // The first crossing lies above the next sub-row's ray (the bottom ray hit the grid's side
    // wall, seen from outside the grid): the per-ray march takes over, as from marchPlane
    const bool inGrid = (sx > 0 ? b.i <= b.majLast : b.i >= b.majLast) && b.minLast >= 0;
    if (inGrid) {
      line.j[n] = j;
      line.h0[n] = height(b.level, b.i, j);
      line.h1[n] = height(b.level, b.i, j + 1);
    }
    if (!inGrid || !solveWalking(n, lane) || line.yc[n] > line.rowSlope[n] * line.depth[n]) {
      end(lane, nullptr, false);
      return;
    }
    currentCrossing(n, lane);
    lane.lastSlot = 1 - lane.lastSlot;
    lane.lastLine = b.count;
    // Its values as the state keeps a last crossing's (keepLine copies the others' at the line's end)
    s.yc[n] = line.yc[n];
    s.depth[n] = line.depth[n];
    s.phi[n] = line.phi[n];
    s.heightQ[n] = line.heightQ[n];
    s.j[n] = line.j[n];
    s.jPos[n] = line.jPos[n];
    s.jGuess[n] = line.jNext[n];
    waiting &= ~(1u << n);
    marchingLanes |= 1u << n;
  };

  // The block starts on the nearest lane's line
  const auto nearestWaiting = [&]() {
    int at = 0;
    bool any = false;
    for (unsigned w = waiting; w != 0; w &= w - 1) {
      const Lane& lane = lanes[static_cast<std::size_t>(std::countr_zero(w))];
      if (!any || (lane.joinLine - at) * sx < 0) at = lane.joinLine;
      any = true;
    }
    return std::pair{any, at};
  };
  Crossing onMinor[2];
  std::uint64_t stepsOfLines = 0;  // heights read by the kernel's lanes
  for (auto [any, at] = nearestWaiting(); any;) {
    setLine(at);
    s.level = b.level;
    s.i = b.i;
    for (;;) {
      for (unsigned w = waiting; w != 0; w &= w - 1) {
        const int n = std::countr_zero(w);
        Lane& lane = lanes[static_cast<std::size_t>(n)];
        if ((b.i - lane.joinLine) * sx >= 0) join(n, lane);
      }
      const bool marching = marchingLanes != 0;
      bool switchable = marching && (b.i & 1) == evenParity;
      for (unsigned m = switchable ? marchingLanes : 0u; m != 0; m &= m - 1) {
        const int n = std::countr_zero(m);
        switchable = switchable && s.depth[n] > lanes[static_cast<std::size_t>(n)].switchZc;
      }
      for (unsigned w = switchable ? waiting : 0u; w != 0; w &= w - 1) {
        // Not while a waiting column's start is near (the coarser line half a step ahead might pass
        // it), nor while its own march would start at this level or a finer one
        const Lane& lane = lanes[static_cast<std::size_t>(std::countr_zero(w))];
        switchable = switchable && (lane.joinLine - b.i) * sx >= 2 && lane.column->level > b.level;
      }
      if (!marching) break;  // on to the next waiting lane's line, if any
      ++b.count;
      if (switchable) {
        // Every column's march is past its switch depth: the coarser level's line, half a step ahead
        enterLevel(b.level + 1);
        setLine(b.i >> 1);
        for (unsigned w = waiting; w != 0; w &= w - 1) {
          Lane& lane = lanes[static_cast<std::size_t>(std::countr_zero(w))];
          lane.joinLine = joinLineOf(*lane.column);
        }
        for (unsigned m = marchingLanes; m != 0; m &= m - 1) {
          const int n = std::countr_zero(m);
          setLaneLine(n, lanes[static_cast<std::size_t>(n)]);
          s.jPos[n] = (s.jPos[n] + 0.5) * 0.5 - 0.5;
          s.jGuess[n] = floorToInt(s.jPos[n]);  // the one-column march's guess without a segment
        }
      } else {
        b.i += sx;
        b.dMaj += sx * b.p;
        b.yLine += b.yStep;
        b.zLine += b.zStep;
        for (int n = 0; n < kLaneColumns; ++n) line.base[n] += s.baseStep[n];
      }
      // Off the grid: every march ends on its last crossing
      if ((sx > 0 ? b.i > b.majLast : b.i < b.majLast) || b.minLast < 0) {
        for (unsigned m = marchingLanes; m != 0; m &= m - 1) {
          const int n = std::countr_zero(m);
          Lane& lane = lanes[static_cast<std::size_t>(n)];
          const Crossing& last = lastCrossing(n, lane);
          end(lane, &last, false);
        }
        break;
      }
      readGuesses(marchingLanes);
      line.yLine = b.yLine;
      line.zLine = b.zLine;
      line.yMinor = b.yMinor;
      line.zMinor = b.zMinor;
      line.dMaj = b.dMaj;
      solveLaneLine(line);
      // The lanes where something happens: a guess that missed, a fill, a ray over the terrain
      unsigned events = 0;
      for (int w = 0; w < kLaneColumns / 8; ++w) {
        const unsigned inWord = (marchingLanes >> (8 * w)) & 0xFFu;  // the word's marching lanes
        const unsigned solved = flagBits(line.solved + 8 * w);
        stepsOfLines += 2 * static_cast<std::uint64_t>(bitsSet8(solved & inWord));
        events |= ((~solved | flagBits(line.fills + 8 * w) | flagBits(line.overTerrain + 8 * w)) & inWord) << (8 * w);
      }
      for (; events != 0; events &= events - 1) {
        const int n = std::countr_zero(events);
        Lane& lane = lanes[static_cast<std::size_t>(n)];
        bool fills = line.fills[n] != 0;
        if (line.solved[n] == 0) {
          // The guess missed the segment (or the crossing lies behind the camera)
          if (!solveWalking(n, lane)) {
            const Crossing& last = lastCrossing(n, lane);
            end(lane, &last, false);
            continue;
          }
          fills = line.yc[n] > line.rowSlope[n] * line.depth[n];
        }
        bool lastFilledNothing = !fills;
        Crossing& cur = currentCrossing(n, lane);
        if (fills) {
          Crossing& prev = lastCrossing(n, lane);
          // The crossings of the minor axis's lines in between bound the fill too (PlaneMarch.cpp)
          int minorCrossings = 0;
          if (cur.depth < b.minorLinesDepth && prev.level == b.level && prev.i == b.i - sx) {
            const MarchLine on{b.level,       b.i,     sx,      line.gA[n],  line.nZ[n], line.base[n],
                               s.baseStep[n], b.yLine, b.yStep, b.zLine,     b.zStep,    b.yMinor,
                               b.zMinor,      c0.upZ,  c0.fwdZ, lane.stretch};
            minorCrossings = solveMinorLines(on, height, prev, cur, onMinor, lane.steps);
          }
          Crossing* from = &prev;
          bool full = false;
          for (int m = 0; m < minorCrossings && !full; ++m) {
            Crossing& mid = onMinor[m];
            if (mid.yc > line.rowSlope[n] * mid.depth && fillBetween(n, lane, *from, mid)) {
              end(lane, &mid, false);
              full = true;
            }
            from = &mid;
          }
          if (full) continue;
          if (cur.yc > line.rowSlope[n] * cur.depth) {
            if (fillBetween(n, lane, *from, cur)) {
              end(lane, &cur, false);
              continue;
            }
          } else {
            lastFilledNothing = true;  // a crossing of a minor line hides it
          }
        }
        // Terrain past the crossing that rows see (lookPastCrossing); here only past a crossing that
        // bounds a fill or needed solving, not the rest of the line's
        if (kSticks && mayLookPastCrossing(f, line.gA[n], line.nZ[n], line.base[n], b.zLine, b.zMinor, c0.fwdZ,
                                           b.lookPastLinesDepth, cur)) {
          const MarchLine on{b.level,       b.i,     sx,      line.gA[n],  line.nZ[n], line.base[n],
                             s.baseStep[n], b.yLine, b.yStep, b.zLine,     b.zStep,    b.yMinor,
                             b.zMinor,      c0.upZ,  c0.fwdZ, lane.stretch};
          lookPastCrossing(f, *lane.c, on, b.minLast, height, cur, lane.q, lane.column->sink->s,
                           lane.column->passedOver, lane.steps);
        }
        // The crossing is the lane's last now, made whole (with its colour or stick once a fill looked
        // them up, and its level-of-detail depth of before the fill, as the one-column march keeps it)
        lane.lastSlot = 1 - lane.lastSlot;
        lane.lastLine = b.count;
        // A row ray above all the terrain and climbing meets nothing more: the rows left see the sky
        // (the kernel's test again, here: a fill up to a minor line's crossing moved the ray since)
        if (lastFilledNothing && line.rayClimbs[n] > 0.0 && c0.cZ + b.dMaj * line.rayZPerDMaj[n] > f.ceilingQ) {
          end(lane, &cur, true);
        }
      }
      keepLine();
    }
    std::tie(any, at) = nearestWaiting();
  }
  t.steps += stepsOfLines;
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
