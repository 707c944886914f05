// The column-plane march (PlaneMarch.h): vertical ray coherence (Cohen-Or, Rich, Lerner,
// Shenkar: "A real-time photo-realistic visual flythrough", 1996) done exactly for tilted columns.
#include "PlaneMarch.h"

#include "CrossingFill.h"
#include "RayMarch.h"
#include "SpanFill.h"
#include "TileWindows.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <tuple>
#include <utility>

namespace fieldcast::core::plane_march {

// The grid helpers and the tile access it shares with the per-ray march (it never marches a ray
// of its own).
using ray_march::ceilToInt;
using ray_march::floorToInt;
using ray_march::heightAt;
using ray_march::levelIndex;
using ray_march::pow2;

namespace {

// Where the ray of the next sub-row ended its march (marchPlaneAxis's advanceRowRay), and why.
struct RowRayEnd {
  enum Why {
    kBelow,          // the ray is below the terrain on `line`: that line's crossing fills the sub-row
    kLevel,          // `line` is even and the ray is past the switch depth there: the march may switch
    kEdge,           // `line` is the grid's last, or the ray leaves the grid's minor extent on it
    kLeavesTerrain,  // the ray is above the highest terrain and climbing: it meets nothing more
    kNotAlong,       // the ray does not run along the march (near the nadir): not marched
  };
  Why why;
  int line;          // where it stopped
  double minor;      // the ray's minor position there (level-L index)
  double minorStep;  // its change per line
};

// marchPlane (PlaneMarch.h) along one major axis.
// kSticks: the terrain has sticks. A separate instance: the stick test and fill in the fill path,
// even never taken, made the frames of a terrain without sticks 7% slower (scripts/render-ab.sh
// down and oblique, 9 rounds each).
template <bool kXMajor, bool kSticks>
int marchPlaneAxis(const CasterFrame& f, CasterThread& t, ColumnSink& sink, const ColumnPlane& c, int q,
                   const glm::dvec2& start, int level, PlaneStop& stopped, PlaneMarchState& state, double pauseDepth,
                   TileWindows& window) noexcept {
  const bool resuming = state.started;
  state.paused = false;
  if (resuming) {
    q = state.q;
    level = state.level;
  }
  const Intrinsics& k = f.geo->intrinsics();
  const int sx = c.sx;
  const double invS = 1.0 / sink.s;
  const double lodDepth = f.geo->lodDepth0M();
  const double cMinHalf = 0.5 + c.cMin;
  const auto& majSizes = c.xMajor ? f.levelWidth : f.levelHeight;
  const auto& minSizes = c.xMajor ? f.levelHeight : f.levelWidth;
  // The tile of the current level the heights come from, kept in registers
  HeightWindow heights(f);
  const auto height = [&](int lv, int i, int j) __attribute__((always_inline))->double {
    return kXMajor ? heights.read(f, t, window, lv, i, j) : heights.read(f, t, window, lv, j, i);
  };

  // The crossing on grid line i at minor position j + φ (level units) solves g = gA·(j + φ) + nZ·h +
  // base = 0; its camera coordinates are yc = yLine + (j + φ)·yMinor + h·upZ and zc likewise. base,
  // yLine and zLine carry the grid line's major position and grow by a constant step per line, so
  // the hot loop keeps few values live (more than the 16 vector registers made it spill).
  const double nZ = c.nZ, upZ = c.upZ, fwdZ = c.fwdZ;
  double p = 0, gA = 0, baseStep = 0, minOffset = 0, yMinor = 0, zMinor = 0, yStep = 0, zStep = 0;
  double switchDepth = 0;
  // Nearer than this a voxel of the level spans kMinorLinesVoxelPx pixels or more: there the fills
  // are bounded by the minor axis's grid lines too (see the fill below).
  const double minorLinesDepth0 = k.fxPx / (f.unitsPerM * kMinorLinesVoxelPx);
  double minorLinesDepth = 0;
  int majLast = 0, minLast = 0;
  // Nearer than this a voxel of the level spans f.lookPastVoxelPx pixels or more
  const double lookPastLinesDepth0 = k.fxPx / (f.unitsPerM * f.lookPastVoxelPx);
  double lookPastLinesDepth = 0;
  // Crossings nearer than this may have terrain past them that rows see (mayLookPastCrossing): a
  // bound per level, so that farther crossings, nearly all of them, pay one compare
  double lookPastDepth = 0;
  const auto enterLevel = [&](int lv) __attribute__((always_inline)) {
    p = pow2(lv);
    gA = c.nMin * p;
    baseStep = c.nMaj * sx * p;
    minOffset = 0.5 * p - cMinHalf;  // minor offset from the camera of segment 0's start
    yMinor = c.upMin * p;
    zMinor = c.fwdMin * p;
    yStep = c.upMaj * sx * p;
    zStep = c.fwdMaj * sx * p;
    switchDepth = lv + 1 < f.levels ? lodDepth * p : std::numeric_limits<double>::infinity();
    minorLinesDepth = minorLinesDepth0 * p;
    lookPastLinesDepth = lookPastLinesDepth0 * p;
    heights.reset();  // the register window belongs to the old level
    // Last grid line inside both the level's grid and the hull of the level-0 voxel centres.
    const int hullLast = sx > 0 ? floorToInt(levelIndex(c.majSize - 1, lv)) : ceilToInt(levelIndex(0.0, lv));
    majLast = sx > 0 ? std::min(hullLast, majSizes[static_cast<std::size_t>(lv)] - 1) : std::max(hullLast, 0);
    minLast = minSizes[static_cast<std::size_t>(lv)] - 2;
    if (kSticks) {
      // The depth changes along L_i by |zMinor − gA/nZ·fwdZ| a voxel, over at most the voxels
      // mayLookPastCrossing looks along
      const double reach = f.stickReachQ * std::abs(nZ);
      lookPastDepth =
          reach > 0.5 * gA ? lookPastLinesDepth + (2.0 * reach / gA + 2.0) * std::abs(zMinor - gA / nZ * fwdZ) : -1.0;
    }
  };
  const double startMaj = c.xMajor ? start.x : start.y;
  const double startMin = c.xMajor ? start.y : start.x;
  enterLevel(level);
  int i = sx > 0 ? floorToInt(levelIndex(startMaj, level)) : ceilToInt(levelIndex(startMaj, level));
  const auto dMajOf = [&](int line) { return (line + 0.5) * p - 0.5 - c.cMaj; };
  double base = 0, yLine = 0, zLine = 0;
  const auto setLine = [&](int line) __attribute__((always_inline)) {
    const double dMaj = dMajOf(line);
    base = c.nMaj * dMaj + c.nMin * minOffset - c.nZ * c.cZ;
    yLine = dMaj * c.upMaj + minOffset * c.upMin - c.cZ * upZ;
    zLine = dMaj * c.fwdMaj + minOffset * c.fwdMin - c.cZ * fwdZ;
  };
  setLine(i);
  double jPos = levelIndex(startMin, level);  // predicted minor position of the next crossing
  constexpr int kNoGuess = std::numeric_limits<int>::min();
  int jGuess = kNoGuess;                       // floor(jPos) when the last solve found it without the division
  const double drift = -c.nMaj / c.nMin * sx;  // minor change of the plane's trace per major step
  if (resuming) {
    i = state.i;
    base = state.base;
    yLine = state.yLine;
    zLine = state.zLine;
    jPos = state.jPos;
    jGuess = state.jGuess;
  }

  // The last crossing (prev) and the one being found (cur).
  Crossing* prevP = &state.crossings[state.prev];
  Crossing* curP = &state.crossings[1 - state.prev];
  std::uint64_t steps = 0;
  // The grazing-angle stretch of the level of detail (ViewGeometry::lodStretch) for the ray of the
  // next sub-row to fill. It only grows as the rows go up the column, so levels still only go up.
  const CameraAxes& axes = f.geo->axes();
  const auto stretchOfRow = [&](int row) __attribute__((always_inline)) {
    const double yc = (k.cyPx - (row + 0.5) * invS) / k.fyPx;
    return f.geo->lodStretch(c.xc * axes.right + yc * axes.up + axes.forward);
  };
  const bool grazingLod = f.geo->grazingLod();
  double stretch = grazingLod ? stretchOfRow(q) : 1.0;
  // The march switches level once a crossing's depth passes switchDepth / stretch.
  double switchZc = switchDepth / stretch;
  // Solves the crossing on the current grid line; false when it leaves the grid or the view.
  const auto solve = [&](Crossing & out) __attribute__((always_inline))->bool {
    if (sx > 0 ? i > majLast : i < majLast) return false;
    if (minLast < 0) return false;
    int j = jGuess != kNoGuess ? jGuess : floorToInt(jPos);
    j = j < 0 ? 0 : (j > minLast ? minLast : j);
    double h0 = height(level, i, j);
    double h1 = height(level, i, j + 1);
    double g0 = gA * j + nZ * h0 + base;
    double g1 = g0 + gA + nZ * (h1 - h0);
    std::uint64_t samples = 2;
    // g grows along the minor axis: walk to the segment where it changes sign.
    const auto heightAt = [&](int at) __attribute__((always_inline)) { return height(level, i, at); };
    if (!walkToCrossing(j, h0, h1, g0, g1, gA, nZ, minLast, heightAt, samples)) return false;
    steps += samples;
    // The crossing at fraction φ along segment j .. j+1 (g0 ≤ 0 < g1), and its camera coordinates.
    const double phi = g0 / (g0 - g1);
    const double minor = j + phi;
    const double h = h0 + phi * (h1 - h0);
    const double zc = zLine + minor * zMinor + h * fwdZ;
    if (!(zc > 1e-6)) return false;
    out.yc = yLine + minor * yMinor + h * upZ;
    out.depth = zc;
    out.lodDepth = zc * stretch;
    out.phi = phi;
    out.level = level;
    out.i = i;
    out.j = j;
    out.haveColour = false;
    out.heightQ = h;
    out.haveStick = false;
    jPos = minor + drift;
    jGuess = nextSegment(j, g0, g1, drift);
    return true;
  };

  if (!resuming && !solve(*prevP)) {
    t.steps += steps;
    return q;
  }
  // Where the march stopped: the last crossing solved, in level-0 x, y.
  const auto recordStop = [&](const Crossing& last) __attribute__((always_inline)) {
    const double lp = pow2(last.level);
    const double maj = (last.i + 0.5) * lp - 0.5;
    const double min = (last.j + 0.5 + last.phi) * lp - 0.5;
    stopped = PlaneStop{true, kXMajor, kXMajor ? glm::dvec2{maj, min} : glm::dvec2{min, maj}};
    t.steps += steps;
  };
  double vq = resuming ? state.vq : (q + 0.5) * invS;
  const ColumnFill fill{f.shading.pixelShader(),
                        static_cast<float>(invS),
                        static_cast<float>(k.cyPx),
                        static_cast<float>(1.0 / k.fyPx),
                        static_cast<float>(1.0 + c.xc * c.xc),
                        invS,
                        sink.qTop};
  const double invFy = 1.0 / k.fyPx;
  double rowSlope = (k.cyPx - vq) * invFy;  // yc / zc of the next sub-row's ray
  if (!resuming && prevP->yc > rowSlope * prevP->depth) {
    // The first crossing already lies above the next sub-row's ray (the bottom ray hit the grid's
    // side wall, seen from outside the grid): it cannot bound a fill, the per-ray march takes over.
    t.steps += steps;
    return q;
  }
  bool lastFilledNothing = resuming && state.lastFilledNothing;  // the last crossing filled no row
  bool skippedSincePrev = false;  // grid lines were passed over since the last crossing solved
  constexpr double kNoSeed = std::numeric_limits<double>::infinity();
  double beforeSeed = kNoSeed;  // where to search the line before for its crossing, if known
  bool rayWaitsForSwitch = resuming && state.rayWaitsForSwitch;  // a level switch the row ray waits for
  // i & 1 on the "even" lines, where the march may switch to the coarser level: there the coarser
  // level's line lies half a step ahead (odd indices when the march runs down the axis).
  const int evenParity = sx > 0 ? 0 : 1;
  // The ray of the next sub-row, marched from grid line i on the level's surface as the per-ray
  // march does: on each line, the height at the ray's minor position against the ray's. While the
  // ray stays above the terrain, no crossing of those lines reaches the sub-row, so none fills
  // anything and none needs solving. Each line is two loads and a compare that do not wait on the
  // line before (a crossing waits on the previous one's segment), so this runs at the loads' rate.
  // It stops on the first line where the ray is below the terrain, or where the march must look
  // itself (see RowRayEnd). "Past the switch depth" is the ray's depth there; the march switches
  // on the crossing's, which can be nearer (looking up) or deeper (looking down).
  const auto advanceRowRay = [&]() __attribute__((always_inline))->RowRayEnd {
    // The ray a + rowSlope·b in grid space, per metre of depth (level-0 units, height quanta).
    const double rMaj = c.aMaj + rowSlope * c.bMaj;
    const double rMin = c.aMin + rowSlope * c.bMin, rZ = c.aZ + rowSlope * c.bZ;
    // It must run along the march, and not so steeply across it that its minor index could leave
    // the int range over the grid (near the nadir).
    if (!(rMaj * sx > 1e-12 && rMaj * sx > 1e-4 * std::abs(rMin))) return {RowRayEnd::kNotAlong, i, 0.0, 0.0};
    const double invR = 1.0 / rMaj;
    const double depth = dMajOf(i) * invR;
    const double dDepth = sx * p * invR;                      // depth per level-L line
    double minor = levelIndex(c.cMin + depth * rMin, level);  // level-L index
    double z = c.cZ + depth * rZ;
    const double dMinor = sx * invR * rMin;
    const double dz = dDepth * rZ;
    int lines = (majLast - i) * sx;
    RowRayEnd::Why end = RowRayEnd::kEdge;  // why it stops if it stays above the terrain
    if (dz >= 0.0) {
      // Once above the highest terrain and climbing, it meets nothing.
      const double below = (f.ceilingQ - z) / dz;
      if (below < 0.0) return {RowRayEnd::kLeavesTerrain, i, minor, dMinor};
      if (below < lines) {
        lines = static_cast<int>(below) + 1;
        end = RowRayEnd::kLeavesTerrain;
      }
    }
    if (switchZc < std::numeric_limits<double>::infinity()) {
      const double before = (switchZc - depth) / dDepth;  // lines before the switch depth
      int n = before < 1.0 ? 1 : (before < lines ? static_cast<int>(before) + 1 : lines);
      n += ((i + n * sx) ^ evenParity) & 1;  // onto an even line (no branch: its outcome is random)
      if (n < lines) {
        lines = n;
        end = RowRayEnd::kLevel;
      }
    }
    int line = i;
    for (int n = 0; n < lines; ++n) {
      line += sx;
      minor += dMinor;
      z += dz;
      const int j = floorToInt(minor);
      if (j < 0 || j > minLast) return {RowRayEnd::kEdge, line, minor, dMinor};
      double h0, h1;
      const int x = kXMajor ? line : j;
      const int y = kXMajor ? j : line;
      if (heights.holds(x, y, kXMajor ? 0 : 1, kXMajor ? 1 : 0)) {
        // Both voxels in the register window: one check for the pair.
        const std::uint16_t* pair = heights.heights + heights.index(x, y);
        h0 = pair[0];
        h1 = pair[kXMajor ? std::ptrdiff_t{1} << f.tileShift : 1];
      } else {
        h0 = height(level, line, j);
        h1 = height(level, line, j + 1);
      }
      if (z < h0 + (minor - j) * (h1 - h0)) {
        steps += 2 * static_cast<std::uint64_t>(n + 1);
        return {RowRayEnd::kBelow, line, minor, dMinor};
      }
    }
    steps += 2 * static_cast<std::uint64_t>(lines);
    return {end, line, minor, dMinor};
  };
  // Fills the sub-rows from the next one up to `to`'s row, which see the terrain between the
  // crossings `from` and `to`, interpolated perspective-correctly; true when the column is full.
  const auto fillBetween = [&](Crossing & from, Crossing & to) __attribute__((always_inline))->bool {
    const int qFirst = q;
    fillCrossings<kSticks>(f, t, window, c, sink, fill, from, to, q, vq);
    rowSlope = (k.cyPx - vq) * invFy;
    if (grazingLod) {
      stretch = stretchOfRow(q);
      switchZc = switchDepth / stretch;
    }
    t.rays += static_cast<std::uint64_t>(qFirst - q);
    return q < fill.qTop;
  };
  // The crossings of minor lines between two of the major axis (solveMinorLines): here, not in the
  // loop, where zeroing them before every fill was 6% of a furnished frame's march
  Crossing onMinor[2];
  for (;;) {
    if (prevP->depth > pauseDepth) {
      // Past the depth band: the next columns march it before this one goes on.
      ++t.pauses;
      state.started = true;
      state.paused = true;
      state.level = level;
      state.i = i;
      state.q = q;
      state.jGuess = jGuess;
      state.prev = static_cast<int>(prevP - state.crossings);
      state.base = base;
      state.yLine = yLine;
      state.zLine = zLine;
      state.jPos = jPos;
      state.vq = vq;
      state.lastFilledNothing = lastFilledNothing;
      state.rayWaitsForSwitch = rayWaitsForSwitch;
      t.steps += steps;
      return q;
    }
    Crossing& prev = *prevP;
    Crossing& cur = *curP;
    bool solved = false;
    // After a crossing that filled nothing, the next lines' crossings fill nothing either until the
    // next sub-row's ray passes below the terrain: found by marching that ray, and only the
    // crossing of the line where it does is solved (and the one before, if that one fills).
    if (lastFilledNothing && !rayWaitsForSwitch && !(prev.depth > switchZc && (i & 1) == evenParity)) {
      const RowRayEnd end = advanceRowRay();
      if (end.why == RowRayEnd::kLeavesTerrain) {
        recordStop(prev);
        stopped.overTerrain = true;
        return q;
      }
      // Looking up, the ray passes the switch depth before the crossings do: after a stop there that
      // did not switch, the march goes line by line until it does (else it would stop every other
      // line), and the ray waits for the next level.
      rayWaitsForSwitch = end.why == RowRayEnd::kLevel;
      if (end.line != i) {
        const int skipped = (end.line - i) * sx - 1;
        if (skipped > 0) {
          // The crossing is near the ray where the ray went below the terrain; otherwise where the
          // plane's drift takes the last one.
          jPos = end.why == RowRayEnd::kBelow ? end.minor : jPos + drift * skipped;
          jGuess = kNoGuess;
          skippedSincePrev = true;
          beforeSeed = end.why == RowRayEnd::kBelow ? end.minor - end.minorStep : kNoSeed;
        }
        i = end.line;
        setLine(i);
        if (!solve(cur)) {
          recordStop(prev);
          return q;
        }
        solved = true;
      }
    }
    if (!solved) {
      // Next grid line: on an even step past the level's depth, the coarser level's line (half a
      // step ahead); otherwise the next line of this level.
      if (prev.depth > switchZc && (i & 1) == evenParity) {
        rayWaitsForSwitch = false;
        ++level;
        i >>= 1;
        enterLevel(level);
        switchZc = switchDepth / stretch;
        setLine(i);
        jPos = (jPos + 0.5) * 0.5 - 0.5;
        jGuess = kNoGuess;
      } else {
        i += sx;
        base += baseStep;
        yLine += yStep;
        zLine += zStep;
      }
      if (!solve(cur)) {
        recordStop(prev);
        return q;
      }
    }
    // Rows to fill: the next sub-row's ray passes below this crossing (vq > v), without dividing.
    // (prev lies below that ray: it filled rows up to it, or filled nothing.)
    const bool fills = cur.yc > rowSlope * cur.depth;
    lastFilledNothing = !fills;
    if (fills && skippedSincePrev) {
      // The crossing before this one was skipped: solve it now, it bounds the rows to fill. It is
      // searched for from the row ray's position on that line, and kept only if it lies below the
      // row ray as the ray's march found (a grid line may cross the column plane's terrain twice);
      // otherwise the fill starts from the last crossing solved.
      const int iHere = i;
      const double baseHere = base, yLineHere = yLine, zLineHere = zLine, jPosHere = jPos;
      const int jGuessHere = jGuess;
      i -= sx;
      setLine(i);
      jPos = beforeSeed != kNoSeed ? beforeSeed : cur.j + cur.phi - drift;
      jGuess = kNoGuess;
      Crossing before{};
      if (solve(before) && !(before.yc > rowSlope * before.depth)) prev = before;
      i = iHere;
      base = baseHere;
      yLine = yLineHere;
      zLine = zLineHere;
      jPos = jPosHere;
      jGuess = jGuessHere;
    }
    skippedSincePrev = false;
    beforeSeed = kNoSeed;
    if (fills) {
      // Between two lines of the major axis the column's terrain may cross lines of the minor axis:
      // their crossings bound the fill too. Without them a column sampled only the lines of its
      // own major axis, and where the columns' major axis changes (looking along a grid diagonal)
      // the image changed from one set of samples to the other in one column: a seam, plain close
      // up where a voxel spans many rows (DiagonalSeam test).
      int minorCrossings = 0;
      if (cur.depth < minorLinesDepth && prev.level == level && prev.i == i - sx) {
        const MarchLine line{level, i,     sx,    gA,     nZ,     base, baseStep, yLine,
                             yStep, zLine, zStep, yMinor, zMinor, upZ,  fwdZ,     stretch};
        minorCrossings = solveMinorLines(line, height, prev, cur, onMinor, steps);
      }
      Crossing* from = &prev;
      for (int m = 0; m < minorCrossings; ++m) {
        Crossing& mid = onMinor[m];
        if (mid.yc > rowSlope * mid.depth && fillBetween(*from, mid)) {
          recordStop(mid);
          return -1;
        }
        from = &mid;
      }
      if (cur.yc > rowSlope * cur.depth) {
        if (fillBetween(*from, cur)) {
          recordStop(cur);
          return -1;
        }
      } else {
        lastFilledNothing = true;  // a crossing of a minor line hides it
      }
    }
    if (kSticks && cur.depth < lookPastDepth &&
        mayLookPastCrossing(f, gA, nZ, base, zLine, zMinor, fwdZ, lookPastLinesDepth, cur)) {
      const MarchLine line{level, i,     sx,    gA,     nZ,     base, baseStep, yLine,
                           yStep, zLine, zStep, yMinor, zMinor, upZ,  fwdZ,     stretch};
      lookPastCrossing(f, c, line, minLast, height, cur, q, sink.s, state.passedOver, steps);
    }
    std::swap(prevP, curP);
  }
}

}  // namespace

ColumnPlane columnPlane(const CasterFrame& f, double uc) noexcept {
  const ViewGeometry& geo = *f.geo;
  const Intrinsics& k = geo.intrinsics();
  const CameraAxes& ax = geo.axes();
  ColumnPlane c;
  c.xc = (uc - k.cxPx) / k.fxPx;
  const double sp = 1.0 / f.unitsPerM;
  const double hs = 1.0 / f.quantaPerM;
  // Plane directions in grid space: the column's central direction and the camera's up axis.
  const glm::dvec3 aw = c.xc * ax.right + ax.forward;
  const glm::dvec3 a{aw.x * f.unitsPerM, aw.y * f.unitsPerM, aw.z * f.quantaPerM};
  const glm::dvec3 b{ax.up.x * f.unitsPerM, ax.up.y * f.unitsPerM, ax.up.z * f.quantaPerM};
  glm::dvec3 n = glm::cross(a, b);
  c.xMajor = std::abs(n.y) >= std::abs(n.x);  // the plane's ground trace runs along (n.y, −n.x)
  const double nMin = c.xMajor ? n.y : n.x;
  if (nMin < 0.0) n = -n;
  // (major, minor) components of a horizontal vector, by the plane's major axis.
  const auto majMin = [&c](double x, double y) { return c.xMajor ? std::pair{x, y} : std::pair{y, x}; };
  std::tie(c.nMaj, c.nMin) = majMin(n.x, n.y);
  c.nZ = n.z;
  std::tie(c.cMaj, c.cMin) = majMin(f.camX, f.camY);
  c.cZ = f.camZq;
  std::tie(c.aMaj, c.aMin) = majMin(a.x, a.y);
  c.aZ = a.z;
  std::tie(c.bMaj, c.bMin) = majMin(b.x, b.y);
  c.bZ = b.z;
  std::tie(c.upMaj, c.upMin) = majMin(ax.up.x * sp, ax.up.y * sp);
  c.upZ = ax.up.z * hs;
  std::tie(c.fwdMaj, c.fwdMin) = majMin(ax.forward.x * sp, ax.forward.y * sp);
  c.fwdZ = ax.forward.z * hs;
  c.vHorizon = ax.up.z > 1e-12 ? k.cyPx + k.fyPx * aw.z / ax.up.z : (aw.z > 0 ? 1e30 : -1e30);
  std::tie(c.majSize, c.minSize) =
      c.xMajor ? std::pair{f.levelWidth[0], f.levelHeight[0]} : std::pair{f.levelHeight[0], f.levelWidth[0]};
  // Rows go up the image as the ground point moves along up_z·d_h − d_z·up_h (d: a ray of the
  // column; the direction is the same for every ray that looks down).
  const glm::dvec3 d = a + (-0.5) * b;  // a ray below the centre row
  const double dirMaj = b.z * (c.xMajor ? d.x : d.y) - d.z * (c.xMajor ? b.x : b.y);
  c.sx = dirMaj >= 0.0 ? 1 : -1;
  return c;
}

int marchPlane(const CasterFrame& f, CasterThread& t, ColumnSink& sink, const ColumnPlane& c, int q,
               const glm::dvec2& start, int level, PlaneStop& stopped, PlaneMarchState& state, double pauseDepth,
               TileWindows& window) noexcept {
  if (f.sticks != nullptr) {
    return c.xMajor ? marchPlaneAxis<true, true>(f, t, sink, c, q, start, level, stopped, state, pauseDepth, window)
                    : marchPlaneAxis<false, true>(f, t, sink, c, q, start, level, stopped, state, pauseDepth, window);
  }
  return c.xMajor ? marchPlaneAxis<true, false>(f, t, sink, c, q, start, level, stopped, state, pauseDepth, window)
                  : marchPlaneAxis<false, false>(f, t, sink, c, q, start, level, stopped, state, pauseDepth, window);
}

}  // namespace fieldcast::core::plane_march
