#pragma once
// The column-plane march. All rays of an image column lie in one plane Π through the camera (for
// a pitched camera Π is tilted, not vertical). On each grid line M = M_i of the column's major
// axis, Π cuts a line L_i; where L_i crosses the terrain profile of that grid line (linear between
// voxel centres along the minor axis) is the one terrain point of this grid line that the column
// sees, and projecting it gives the image row v_i where it appears. Walking the grid lines away
// from the camera, the rows between the highest crossing so far and v_i see the terrain between
// grid lines i−1 and i: they are filled by interpolating the two crossings (perspective-correct).
// This is the vertical coherence of Cohen-Or, Rich, Lerner and Shenkar ("A real-time
// photo-realistic visual flythrough", 1996) done exactly for tilted columns: every ray of
// the column is tested at every grid line, yet the work is one crossing per grid line plus one
// fill per pixel, with no per-ray set-up.
//
// castColumns (ColumnCaster.cpp) drives it: a column's march can pause at a depth and resume, so
// the columns of a staging block march in step. Private to ig_core.

#include "ColumnCaster.h"
#include "StickShading.h"
#include "TileWindows.h"

#include <glm/vec2.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace fieldcast::core::plane_march {

/// The plane Π of one image column, with the camera axes and the column ray, in grid space:
/// x, y in level-0 voxel units, z in height quanta.
struct ColumnPlane {
  bool xMajor = true;
  int sx = 1;                               ///< march direction along the major axis (rows go up)
  double nMaj = 0, nMin = 1, nZ = 0;        ///< plane normal in grid space, oriented so nMin > 0
  double cMaj = 0, cMin = 0, cZ = 0;        ///< camera in grid space
  double upMaj = 0, upMin = 0, upZ = 0;     ///< camera up axis, grid deltas → metres
  double fwdMaj = 0, fwdMin = 0, fwdZ = 0;  ///< camera forward axis, grid deltas → metres
  double aMaj = 0, aMin = 0, aZ = 0;        ///< the column ray at yc = 0, grid space: ray(yc) = a + yc·b
  double bMaj = 0, bMin = 0, bZ = 0;        ///< the camera up axis, grid space
  double vHorizon = 0;                      ///< rows above this (smaller v) look upwards
  double xc = 0;                            ///< camera-space x of the column (ray = (xc, yc, 1))
  int majSize = 0, minSize = 0;             ///< level-0 grid size along major / minor
};

/// The terrain point of one grid line that the column sees. It is kept in camera space (yc, zc):
/// most crossings at low pitch raise the column by less than a row, and telling that (and whether
/// a crossing is hidden) takes a multiply, not a division. Only a crossing that bounds a fill is
/// projected to its image row; only one that colours a pixel gets a colour.
struct Crossing {
  double yc = 0;        ///< camera up coordinate (metres)
  double depth = 0;     ///< camera forward coordinate zc (metres)
  double phi = 0;       ///< fraction along the segment
  double lodDepth = 0;  ///< depth the level of detail is chosen for (depth × lodStretch)
  int level = 0;
  int i = 0;  ///< level-L major index of the grid line
  int j = 0;  ///< minor segment j .. j+1 (level-L indices)
  /// On a grid line of the minor axis instead (see marchPlaneAxis): j is that line, the crossing
  /// lies on major segment i .. i+1 at fraction phi.
  bool onMinorLine = false;
  bool haveColour = false;
  Rgb colour;
  double heightQ = 0;  ///< the terrain's height there (quanta)
  /// On a terrain with sticks, the stick that colours it (none: id 0), once looked up.
  bool haveStick = false;
  StickVoxel stick;
};

/// The plane of the column through pixel column centre uc, in grid space.
ColumnPlane columnPlane(const CasterFrame& f, double uc) noexcept;

/// Collects the sub-rows of a column (bottom to top) into pixels of a column-major staging block.
struct ColumnSink {
  const CasterFrame& f;
  int s;
  float scale;
  Rgb sum;
  float range = std::numeric_limits<float>::infinity();
  std::uint8_t* pixels = nullptr;  ///< this column's pixel in row 0 (rows are consecutive)
  std::size_t bytesPerPixel = 0;
  float* ranges = nullptr;  ///< this column's range in row 0 (rows are consecutive)
  int qTop = 0;             ///< the column's top sub-row: its rows above the frame's footprint are not cast

  ColumnSink(const CasterFrame& frame, int subRows, std::uint8_t* columnPixels, float* columnRanges) noexcept
      : f(frame), s(subRows), scale(1.0f / static_cast<float>(subRows)) {
    if (f.image != nullptr) {
      bytesPerPixel = static_cast<std::size_t>(f.shading.bytesPerPixel());
      pixels = columnPixels;
    }
    if (f.rangeM != nullptr) ranges = columnRanges;
  }

  /// Writes pixel v: colour `c` × `k`, and its range.
  void put(int v, const Rgb& c, float rangeM, float k) const noexcept {
    if (pixels != nullptr) f.shading.storePixel(pixels + static_cast<std::size_t>(v) * bytesPerPixel, c, k);
    if (ranges != nullptr) ranges[v] = rangeM;
  }

  /// Takes sub-row q (bottom to top); with s sub-rows per pixel, a pixel gets the mean of its
  /// colours and its middle sub-row's range once its top sub-row is in.
  void emit(int q, const Rgb& c, float rangeM) noexcept {
    if (s == 1) {
      put(q, c, rangeM, 1.0f);
      return;
    }
    sum += c;
    const int sub = q % s;
    if (sub == s / 2) range = rangeM;
    if (sub != 0) return;
    put(q / s, sum, range, scale);
    sum = Rgb{};
    range = std::numeric_limits<float>::infinity();
  }
};

/// Where the column plane march stopped: the level-0 x, y of its last crossing, on a grid line of its
/// major axis. The rays of the rows it left pass above all the terrain of the grid lines before.
struct PlaneStop {
  bool valid = false;
  bool xMajor = false;  ///< the plane's major axis
  glm::dvec2 point{0.0};
  bool overTerrain = false;  ///< the rows left look over all the terrain: they see the sky
};

/// Sub-rows of a column that see terrain its plane march passed over (pieceBeyondCrossing), to be
/// cast ray by ray once the march is done: spans lo .. hi. A span that meets or overlaps the last
/// one is merged into it; past kSpans, a span is merged into the one it lies nearest.
struct RowsPassedOver {
  struct Span {
    int lo = 0, hi = -1;
  };
  static constexpr int kSpans = 16;
  Span spans[kSpans]{};
  int count = 0;
  void add(int lo, int hi) noexcept {
    if (lo > hi) return;
    const auto gap = [&](const Span& s) { return lo > s.hi ? lo - s.hi : (s.lo > hi ? s.lo - hi : 0); };
    int into = count - 1;
    if (count == kSpans) {
      for (int n = 0; n < count; ++n) into = gap(spans[n]) < gap(spans[into]) ? n : into;
    } else if (count == 0 || gap(spans[into]) > 1) {
      spans[count++] = Span{lo, hi};
      return;
    }
    Span& s = spans[into];
    s.lo = lo < s.lo ? lo : s.lo;
    s.hi = hi > s.hi ? hi : s.hi;
  }
};

/// What the plane march of a column carries from one grid line to the next, so that it can pause
/// at a depth and resume there. castColumns marches the columns of a staging block in step, depth
/// band by depth band: all but the first then read heights and texels already in L1.
/// (What the loop recomputes from these, such as the level's steps, the next row's slope and the
/// grazing-angle stretch, is not kept.)
struct PlaneMarchState {
  bool started = false;  ///< the march has paused once: the next call resumes from here
  bool paused = false;   ///< the last call paused (rather than ended)
  int level = 0, i = 0, q = 0, jGuess = 0, prev = 0;
  double base = 0, yLine = 0, zLine = 0, jPos = 0, vq = 0;
  bool lastFilledNothing = false, rayWaitsForSwitch = false;
  Crossing crossings[2]{};
  RowsPassedOver passedOver;  ///< rows to cast ray by ray once the march is done
};

/// The plane march from the grid line at or before `start` (level-0 x, y of the hit of the ray of
/// sub-row q+1) at `level`, filling sub-rows q, q−1, ... Returns the first sub-row it could not
/// fill (−1 when the column is done): the march left the terrain, or the rows left look over it.
/// `stopped` records its last crossing, where the per-ray march takes the rows left on. Once its
/// last crossing lies deeper than `pauseDepth` it pauses instead (state.paused); called again with
/// the same state, it goes on from there (q, start and level are then the state's).
int marchPlane(const CasterFrame& f, CasterThread& t, ColumnSink& sink, const ColumnPlane& c, int q,
               const glm::dvec2& start, int level, PlaneStop& stopped, PlaneMarchState& state, double pauseDepth,
               TileWindows& window) noexcept;

/// Where a voxel spans at least this many pixels, a fill between two crossings of the major axis is
/// split at the crossings of the minor axis's grid lines between them. Every column then samples
/// the terrain on the grid lines of both axes, so the image does not change where the columns' major
/// axis does (looking along a grid diagonal). Farther away a fill covers a few pixels and the extra
/// crossings would cost more than they show: splitting every fill made the bench's frames 1.2–2×
/// slower. At 8 pixels the horizon view costs 15% more, at 4 pixels 20%; at 16 the seam shows
/// again (RENDERER.md, "Both axes' grid lines near the camera").
constexpr double kMinorLinesVoxelPx = 8.0;

/// The march looks past a crossing for terrain rising above the column plane's line
/// (mayLookPastCrossing) where a voxel spans kMinorLinesVoxelPx pixels of a frame
/// kLookPastFrameWidthPx wide (an NTSC frame with its margins), or as large a share of a wider
/// frame's width. What the march would get wrong farther is a voxel's worth of picture, whatever
/// the frame's size; the looks' cost grows with their share of it: with an 8-pixel gate at every
/// size, a 2304-pixel-wide frame looking down cast 6% of its pixels ray by ray and took 3.4× as
/// long as without the looks (render/NOTES.md).
constexpr double kLookPastFrameWidthPx = 864.0;
inline double lookPastVoxelPx(int frameWidthPx) noexcept {
  return kMinorLinesVoxelPx * std::max(1.0, frameWidthPx / kLookPastFrameWidthPx);
}

/// The column plane march's next grid line segment, floor(j + φ + drift), for φ = g0 / (g0 − g1)
/// in [0, 1) and |drift| ≤ 1 (the plane's trace runs along the major axis): φ + drift is in
/// [−1, 2), so two comparisons give it without the division. That keeps the division off the
/// chain from one crossing to the next, which bounds the march (it is latency-bound).
inline int nextSegment(int j, double g0, double g1, double drift) noexcept {
  const double dg = g0 - g1;  ///< < 0
  return j + static_cast<int>(g0 <= (1.0 - drift) * dg) - static_cast<int>(g0 > -drift * dg);
}

/// The crossing solve's walk along a grid line: from segment j .. j+1 (heights h0, h1, the plane's
/// g0, g1 there) to the segment where g changes sign (g0 ≤ 0 < g1). g grows along the minor axis by
/// gA per voxel plus nZ times the height's change; heightAt(j) reads the line's voxel j. False when
/// the walk would leave segments 0 .. minLast. Adds the heights it reads to `samples`.
template <typename HeightAt>
__attribute__((always_inline)) inline bool walkToCrossing(int& j, double& h0, double& h1, double& g0, double& g1,
                                                          double gA, double nZ, int minLast, HeightAt&& heightAt,
                                                          std::uint64_t& samples) noexcept {
  while (g0 > 0.0) {
    if (j == 0) return false;
    --j;
    h1 = h0;
    g1 = g0;
    h0 = heightAt(j);
    g0 -= gA + nZ * (h1 - h0);
    ++samples;
  }
  while (g1 <= 0.0) {
    if (j == minLast) return false;
    ++j;
    h0 = h1;
    g0 = g1;
    h1 = heightAt(j + 1);
    g1 = g0 + gA + nZ * (h1 - h0);
    ++samples;
  }
  return true;
}

/// Terrain of a grid line beyond the crossing the march takes on it (RENDERER.md, "Steep terrain in
/// a tilted column plane"). A pitched camera tilts its columns' planes, so the line L_i where a
/// plane cuts grid line i leans; a profile steeper than that lean (a stick's side) can rise above
/// L_i again past the crossing, on the side where L_i rises. The rows that see it there are given
/// the terrain of other lines by the march (lookPastCrossing says which). Scans the voxels of the
/// line past the crossing's segment j .. j+1 that way (the plane's g = gA·minor + nZ·h + base along
/// the line; a voxel is above L_i where g has nZ's sign) while L_i lies less than `reachQ` (the
/// tallest stick) above the crossing's height `heightQ` or a voxel read below it, at most
/// kMaxPieceScan voxels; `before` and `after` get the voxels either side of those above L_i (`after`
/// may lie off the grid). False when none. `samples` counts the heights read.
constexpr int kMaxPieceScan = 64;
template <typename HeightAt>
__attribute__((always_inline)) inline bool pieceBeyondCrossing(int j, double gA, double nZ, double base, double heightQ,
                                                               double reachQ, int minLast, HeightAt&& heightAt,
                                                               int& before, int& after,
                                                               std::uint64_t& samples) noexcept {
  if (nZ == 0.0) return false;  // a vertical plane: L_i is vertical and meets the profile once
  // L_i rises toward the segment's end where g < 0 when nZ > 0 (its first voxel), else its last.
  const int dir = nZ > 0.0 ? -1 : 1;
  const double zPerMinor = -gA / nZ, zAtZero = -base / nZ;  // L_i: z(m) = zAtZero + m·zPerMinor
  double ceilingQ = heightQ + reachQ;
  int m = nZ > 0.0 ? j : j + 1;
  bool found = false;
  for (int n = 0; n < kMaxPieceScan; ++n) {
    m += dir;
    if (m < 0 || m > minLast + 1) break;
    const double zL = zAtZero + m * zPerMinor;
    if (zL > ceilingQ) break;
    ++samples;
    const double h = heightAt(m);
    if (h > zL) {
      if (!found) before = m - dir;
      after = m + dir;
      found = true;
    } else {
      ceilingQ = std::max(ceilingQ, h + reachQ);  // a stick may stand on ground that rises
    }
  }
  return found;
}

}  // namespace fieldcast::core::plane_march
