#pragma once
// What the column-plane marches (PlaneMarch.h, and the lanes of LaneMarch.h) do with a crossing
// once it is solved: its colour (linear along its grid line, blended with the next level, relit for
// the frame's sun), its stick, and the fill of the sub-rows between two crossings. Private to
// ig_core.

#include "PlaneMarch.h"
#include "RayMarch.h"
#include "SpanFill.h"
#include "TileWindows.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace fieldcast::core::plane_march {

// Blends the next level's colour (bilinear) into crossing x's, by `blend`. Out of line: half the
// crossings that are coloured need it, and it reads four texels.
[[gnu::noinline]] void blendNextLevel(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c,
                                      Crossing& x, double blend) noexcept;

// Scales a crossing's colour by the frame's sun (TerrainLight.h) where it lies on its segment.
// Called only for a relit frame.
void relightCrossing(const CasterFrame& f, CasterThread& t, const ColumnPlane& c, Crossing& x) noexcept;

// On a terrain with sticks, where either crossing lies on a stick: fills the sub-rows between
// them with the stick's texels — the far crossing's stick, else the near one's — into the sink (one
// sub-row per pixel or several). Out of line: placed away from the terrain fill's code. (The test
// whether a fill meets a stick at all stays inline in the march of a terrain with sticks: called
// for it, the furnished built-in terrain's frames were 10–25% slower.)
[[gnu::noinline]] void fillOnStick(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c,
                                   const StickVoxel& near, const StickVoxel& far, const Crossing& from,
                                   const Crossing& to, const CrossingSpan& span, const ColumnFill& column,
                                   ColumnSink& sink, double vStop, int& qInOut, double& vqInOut) noexcept;

// Colour of a crossing on a grid line of the minor axis (Crossing::onMinorLine): linear along that
// line between voxels (i, j) and (i + 1, j), blended with the next level as crossingColour does.
[[gnu::noinline]] void minorLineColour(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c,
                                       Crossing& x) noexcept;

// A crossing's stick (StickShading.h): the one of its segment's two voxels that colours it (a
// minor-line crossing's segment runs along the major axis). Looked up once per crossing: every fill
// of a terrain with sticks asks it of both its crossings, most of them have none, and a crossing
// bounds two fills. Where both voxels of the segment lie in one tile (most crossings): one window
// test, and the two voxels' bits, usually both clear, instead of two windowStick reads.
inline const StickVoxel& crossingStick(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c,
                                       Crossing& x) noexcept {
  if (x.haveStick) return x.stick;
  const int vx = c.xMajor ? x.i : x.j;
  const int vy = c.xMajor ? x.j : x.i;
  const bool alongX = c.xMajor == x.onMinorLine;  // the segment's second voxel lies east, else north
  x.haveStick = true;
  if (((alongX ? vx : vy) & f.tileMask) != f.tileMask && windowFor(f, t, w, x.level, vx, vy)) {
    const auto l = static_cast<std::size_t>(x.level);
    const TerrainTile& tile = *w.tile[l];
    const auto index0 = static_cast<std::size_t>(((vy - w.y0[l]) << f.tileShift) + (vx - w.x0[l]));
    const std::size_t index1 = index0 + (alongX ? std::size_t{1} : std::size_t{1} << f.tileShift);
    if (tile.stickId == nullptr || (!tile.hasStick(index0) && !tile.hasStick(index1))) {
      x.stick = StickVoxel{};
      return x.stick;
    }
    x.stick = colouringStick(tileStick(tile, index0, x.level), tileStick(tile, index1, x.level));
    return x.stick;
  }
  x.stick = colouringStick(windowStick(f, t, w, x.level, vx, vy),
                           windowStick(f, t, w, x.level, alongX ? vx + 1 : vx, alongX ? vy : vy + 1));
  return x.stick;
}

// Crossing x's colour from its segment's two voxels' colours c0, c1: linear between them, blended
// with the next level, relit for the frame's sun.
__attribute__((always_inline)) inline void colourCrossing(const CasterFrame& f, CasterThread& t, TileWindows& w,
                                                          const ColumnPlane& c, Crossing& x, std::uint32_t c0,
                                                          std::uint32_t c1) noexcept {
  const int l = x.level;
  x.colour = mix(unpackRgb(c0), unpackRgb(c1), static_cast<float>(x.phi));
  x.haveColour = true;
  if (f.blend && l + 1 < f.levels) {
    const double blend =
        std::clamp(4.0 * x.lodDepth * f.invLodDepth0M * ray_march::pow2(-l) - 3.0, 0.0, 1.0);  // levelBlend
    if (blend > 0.0) blendNextLevel(f, t, w, c, x, blend);
  }
  if (f.shading.light().relit()) relightCrossing(f, t, c, x);
}

// Colour of a crossing: linear along the grid line at its level (minorLineColour on a minor line),
// blended with the next level.
// Inline: it is asked for twice per fill, and as a call its set-up cost as much as its work.
__attribute__((always_inline)) inline const Rgb& crossingColour(const CasterFrame& f, CasterThread& t, TileWindows& w,
                                                                const ColumnPlane& c, Crossing& x) noexcept {
  if (x.haveColour) return x.colour;
  if (x.onMinorLine) {
    minorLineColour(f, t, w, c, x);
    return x.colour;
  }
  const int l = x.level;
  std::uint32_t c0, c1;
  const int vx = c.xMajor ? x.i : x.j;
  const int vy = c.xMajor ? x.j : x.i;
  if ((x.j & f.tileMask) != f.tileMask && windowFor(f, t, w, l, vx, vy)) {
    // Both voxels of the segment lie in one tile: two loads.
    const auto lv = static_cast<std::size_t>(l);
    const std::uint32_t* p0 = w.tile[lv]->colourRgba + (((vy - w.y0[lv]) << f.tileShift) + (vx - w.x0[lv]));
    c0 = p0[0];
    c1 = p0[c.xMajor ? std::ptrdiff_t{1} << f.tileShift : 1];
  } else {
    c0 = windowColour(f, t, w, l, vx, vy);
    c1 = c.xMajor ? windowColour(f, t, w, l, vx, vy + 1) : windowColour(f, t, w, l, vx + 1, vy);
  }
  colourCrossing(f, t, w, c, x, c0, c1);
  return x.colour;
}

// Fills the sub-rows of a supersampled column (several per pixel) between two crossings, as
// fillSpanReference does for one per pixel; the sink averages them into pixels.
__attribute__((always_inline)) inline void fillSpanSubRows(const CrossingSpan span, const ColumnFill& column,
                                                           ColumnSink& sink, double vStop, int& qInOut,
                                                           double& vqInOut) noexcept {
  const PixelShader shading = column.shading;
  forEachSpanRow(span, column, shading, vStop, qInOut, vqInOut,
                 [&](int q, const SpanPixel& p) { sink.emit(q, p.colour, p.rangeM); });
}

/// A grid line of a march's major axis at its level, and the column plane's terms on it
/// (PlaneMarch.cpp's solve: g = gA·minor + nZ·h + base along the line; camera yc, zc likewise from
/// yLine, zLine; each grows by its step per line).
struct MarchLine {
  int level, i, sx;
  double gA, nZ, base, baseStep, yLine, yStep, zLine, zStep, yMinor, zMinor, upZ, fwdZ, stretch;
};

/// The crossings of the minor axis's grid lines that lie strictly between crossing `from` on line
/// i − sx and `to` on line i (both of the line's level), in order from `from`, at most two, into
/// `out`; returns how many. On minor line m the terrain is linear along the major axis between
/// voxels (i − sx, m) and (i, m), and the plane's g changes along it by baseStep + nZ·Δh: a
/// crossing where g changes sign. height(level, major, minor) reads the grid; `steps` counts the
/// reads.
template <typename Height>
__attribute__((always_inline)) inline int solveMinorLines(const MarchLine& line, Height&& height, const Crossing& from,
                                                          const Crossing& to, Crossing* out,
                                                          std::uint64_t& steps) noexcept {
  const double a = from.j + from.phi;
  const double b = to.j + to.phi;
  const int step = b > a ? 1 : -1;
  int m = b > a ? ray_march::floorToInt(a) + 1 : ray_march::ceilToInt(a) - 1;
  int found = 0;
  const int i = line.i, sx = line.sx;
  const double baseFrom = line.base - line.baseStep, yFrom = line.yLine - line.yStep, zFrom = line.zLine - line.zStep;
  for (int n = 0; n < 2 && (m - b) * step < 0.0; ++n, m += step) {
    const double h0 = height(line.level, i - sx, m);
    const double h1 = height(line.level, i, m);
    const double g0 = line.gA * m + line.nZ * h0 + baseFrom;
    const double g1 = g0 + line.baseStep + line.nZ * (h1 - h0);
    steps += 2;
    if ((g0 > 0.0) == (g1 > 0.0)) continue;  // the column's terrain passes this line beyond the two
    const double psi = g0 / (g0 - g1);       // fraction from line i − sx toward line i
    const double h = h0 + psi * (h1 - h0);
    const double zc = zFrom + psi * line.zStep + m * line.zMinor + h * line.fwdZ;
    if (!(zc > 1e-6)) continue;
    Crossing& x = out[found++];
    x.yc = yFrom + psi * line.yStep + m * line.yMinor + h * line.upZ;
    x.depth = zc;
    x.lodDepth = zc * line.stretch;
    x.level = line.level;
    x.i = sx > 0 ? i - 1 : i;
    x.phi = sx > 0 ? psi : 1.0 - psi;
    x.j = m;
    x.onMinorLine = true;
    x.haveColour = false;
    x.heightQ = h;
    x.haveStick = false;
  }
  return found;
}

/// Whether terrain past crossing x on a grid line (the plane's g = gA·minor + nZ·h + base along it,
/// the camera's zc = zLine + minor·zMinor + h·fwdZ) could rise into the column where the march
/// should look for it (lookPastCrossing): the plane leans so far that L_i takes more than half a
/// voxel to climb the tallest stick's height, and a voxel spans f.lookPastVoxelPx pixels or more
/// (nearer than `nearDepth`) at the crossing or as far along L_i as a stick on the
/// crossing's ground could reach (the depth is linear along it; the scan may go farther where the
/// ground rises). Farther, a voxel's worth of terrain passed over is a few pixels, and in a wood,
/// where the next tree along nearly every line rises above it, casting those rows made the frames
/// up to 3× slower (looking down, at 4 px). The one-column march asks it of the crossings nearer
/// than a bound per level, the lane march of every crossing it fills from.
__attribute__((always_inline)) inline bool mayLookPastCrossing(const CasterFrame& f, double gA, double nZ, double base,
                                                               double zLine, double zMinor, double fwdZ,
                                                               double nearDepth, const Crossing& x) noexcept {
  const double reach = f.stickReachQ * std::abs(nZ);  // × gA: the voxels along L_i a stick reaches
  if (!(reach > 0.5 * gA)) return false;
  if (x.depth < nearDepth) return true;
  const double mEnd = x.j + x.phi + (nZ > 0.0 ? -1.0 : 1.0) * (2.0 * reach / gA + 2.0);
  return zLine + mEnd * zMinor - (gA * mEnd + base) / nZ * fwdZ < nearDepth;
}

/// On a terrain with sticks, where mayLookPastCrossing says so: looks past crossing x on `line` for
/// terrain above its line L_i (pieceBeyondCrossing) and adds to `out` the sub-rows that see it
/// there and that the march got wrong. Every such row's ray meets L_i in front of the camera, so
/// it runs along the march where the line lies ahead of the camera along the march's axis, and
/// against it where the line lies behind (a steep column's rays run back under the camera): along,
/// the rows are those above the front it has yet to fill (from q up), which it would fill from the
/// lines after, farther along their rays; against, those below it, filled already from the lines
/// before, which were farther along theirs. `minLast` is the level's last minor segment;
/// height(level, major, minor) reads the grid; `steps` counts the reads.
template <typename Height>
void lookPastCrossing(const CasterFrame& f, const ColumnPlane& c, const MarchLine& line, int minLast, Height&& height,
                      const Crossing& x, int q, int subRows, RowsPassedOver& out, std::uint64_t& steps) noexcept {
  const double gA = line.gA, nZ = line.nZ, base = line.base;
  int before = 0, after = 0;
  const auto heightAt = [&](int at) __attribute__((always_inline)) { return height(line.level, line.i, at); };
  if (!pieceBeyondCrossing(x.j, gA, nZ, base, x.heightQ, f.stickReachQ, minLast, heightAt, before, after, steps))
    return;
  // The rows of L_i's points over the voxels either side of the piece
  const Intrinsics& k = f.geo->intrinsics();
  const auto rowOf = [&](int m, double& v) {
    const double z = -(gA * m + base) / nZ;
    const double zc = line.zLine + m * line.zMinor + z * line.fwdZ;
    if (!(zc > 1e-6)) return false;
    v = k.cyPx - k.fyPx * (line.yLine + m * line.yMinor + z * line.upZ) / zc;
    return true;
  };
  double v0, v1;
  if (!rowOf(before, v0) || !rowOf(after, v1)) return;
  const double s = subRows;
  const double top = std::max(std::min(v0, v1) * s - 0.5, 0.0);
  const double bottom = std::min(std::max(v0, v1) * s - 0.5, k.heightPx * s - 1.0);
  const double dMaj = (line.i + 0.5) * ray_march::pow2(line.level) - 0.5 - c.cMaj;  // the line from the camera
  const bool along = line.sx * dMaj > 0.0;
  const double lo = along ? top : std::max(top, static_cast<double>(q + 1));
  const double hi = along ? std::min(bottom, static_cast<double>(q)) : bottom;
  if (lo <= hi) out.add(ray_march::ceilToInt(lo), ray_march::floorToInt(hi));
}

/// Fills the sub-rows of a column from q (its centre vq) up to crossing `to`'s row, which see what
/// lies between crossings `from` and `to`: the terrain, interpolated perspective-correctly, or a
/// stick's side or top (kSticks: the terrain has sticks). Advances q and vq past the rows filled.
/// Only a crossing that fills rows is projected to its row and coloured.
template <bool kSticks>
__attribute__((always_inline)) inline void fillCrossings(const CasterFrame& f, CasterThread& t, TileWindows& window,
                                                         const ColumnPlane& c, ColumnSink& sink, const ColumnFill& fill,
                                                         Crossing& from, Crossing& to, int& q, double& vq) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const double fromInvDepth = 1.0 / from.depth;
  const double toInvDepth = 1.0 / to.depth;
  const double fromV = k.cyPx - k.fyPx * from.yc * fromInvDepth;
  const double toV = k.cyPx - k.fyPx * to.yc * toInvDepth;
  CrossingSpan span{static_cast<float>(fromV),
                    static_cast<float>(1.0 / (toV - fromV)),
                    static_cast<float>(fromInvDepth),
                    static_cast<float>(toInvDepth),
                    Rgb{},
                    Rgb{}};  // the colours of terrain (not of a stick), once it is known which
  const StickVoxel* near = nullptr;
  const StickVoxel* far = nullptr;
  if constexpr (kSticks) {
    near = &crossingStick(f, t, window, c, from);
    far = &crossingStick(f, t, window, c, to);
  }
  if (kSticks && (near->id != 0 || far->id != 0)) {
    // A stick's side or top, filled with its texels: the crossings' terrain colours are not needed
    fillOnStick(f, t, window, c, *near, *far, from, to, span, fill, sink, toV, q, vq);
  } else {
    span.c0 = crossingColour(f, t, window, c, from);
    span.c1 = crossingColour(f, t, window, c, to);
    if (sink.s != 1) {
      fillSpanSubRows(span, fill, sink, toV, q, vq);
    } else if (fill.shading.grey) {
      fillSpan<true>(span, fill, ColumnPixels{sink.pixels, sink.ranges, sink.bytesPerPixel}, toV, q, vq);
    } else {
      fillSpan<false>(span, fill, ColumnPixels{sink.pixels, sink.ranges, sink.bytesPerPixel}, toV, q, vq);
    }
  }
}

}  // namespace fieldcast::core::plane_march
