// Column ray casting with vertical ray coherence (Cohen-Or, Rich, Lerner, Shenkar: "A real-time
// photo-realistic visual flythrough", 1996): each column's rays below its first hit by the per-ray
// march (RayMarch.h), the rest by the column-plane march (PlaneMarch.h), the columns of a staging
// block in step, and the rows the plane march leaves by the per-ray march again.
#include "ColumnCaster.h"
#include "FrameAssembly.h"
#include "LaneMarch.h"
#include "PlaneMarch.h"
#include "RayMarch.h"
#include "SeeThrough.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>

namespace fieldcast::core {

using namespace ray_march;    // the per-ray march and its grid helpers
using namespace plane_march;  // the column-plane march

std::uint16_t terrainCeilingQ(const TerrainView& view) noexcept {
  const TerrainGeometry& g = view.geometry();
  const int top = g.levels - 1;
  std::uint16_t ceiling = 0;
  for (int j = 0; j < g.levelHeightVox(top); ++j) {
    for (int i = 0; i < g.levelWidthVox(top); ++i) ceiling = std::max(ceiling, view.maxHeightQ(top, i, j));
  }
  return ceiling;
}

std::uint32_t basePlaneColour(const TerrainView& view) noexcept {
  const TerrainGeometry& g = view.geometry();
  const int top = g.levels - 1;
  std::array<double, 3> sum{};
  for (int j = 0; j < g.levelHeightVox(top); ++j) {
    for (int i = 0; i < g.levelWidthVox(top); ++i) {
      const std::uint32_t c = view.colourRgba(top, i, j);
      for (int k = 0; k < 3; ++k) sum[static_cast<std::size_t>(k)] += (c >> (8 * k)) & 0xFFu;
    }
  }
  const double n = static_cast<double>(g.levelWidthVox(top)) * g.levelHeightVox(top);
  std::uint32_t rgba = 0xFF000000u;
  for (int k = 0; k < 3; ++k)
    rgba |= static_cast<std::uint32_t>(std::lround(sum[static_cast<std::size_t>(k)] / n)) << (8 * k);
  return rgba;
}

CasterFrame::CasterFrame(const TerrainView& v, const ViewGeometry& geometry, const RenderSettings& settings,
                         std::uint16_t ceiling, std::uint32_t baseRgba, Image* img, float* range,
                         const FrameFootprint* cast) noexcept
    : view(&v),
      geo(&geometry),
      shading(settings),
      levels(v.geometry().levels),
      tileShift(v.geometry().tileShift),
      tileMask(v.geometry().tileSizeVox() - 1),
      supersample(std::clamp(settings.verticalSupersample, 1, 4)),
      blend(settings.blendLevels),
      laneMarch(settings.laneMarch),
      sticks(v.sticks()),
      footprint(cast != nullptr ? *cast : FrameFootprint{}),
      image(img),
      rangeM(range) {
  if (footprint.whole) {
    footprint.widthPx = geometry.intrinsics().widthPx;
    footprint.heightPx = geometry.intrinsics().heightPx;
  }
  const TerrainGeometry& g = v.geometry();
  if (sticks != nullptr) {
    stickUnitsPerQ = g.heightStepM / sticks->unitM();
    seeThrough = sticks->hasSeeThrough();
    stickReachQ = sticks->longestVox() / stickUnitsPerQ;
    lookPastVoxelPx = plane_march::lookPastVoxelPx(geometry.intrinsics().widthPx);
  }
  for (int l = 0; l < levels; ++l) {
    levelWidth[static_cast<std::size_t>(l)] = g.levelWidthVox(l);
    levelHeight[static_cast<std::size_t>(l)] = g.levelHeightVox(l);
  }
  unitsPerM = 1.0 / g.spacingM;
  quantaPerM = 1.0 / g.heightStepM;
  const glm::dvec3 p = geometry.pose().positionM;
  camX = (p.x - g.originM.x) * unitsPerM;
  camY = (p.y - g.originM.y) * unitsPerM;
  camZq = (p.z - g.heightBaseM) * quantaPerM;
  invLodDepth0M = 1.0 / geometry.lodDepth0M();
  ceilingQ = ceiling;
  baseAboveM = p.z - g.heightBaseM;
  baseColourRgba = baseRgba;
  baseColour = Rgb{unpackRgb(baseRgba).v * shading.light().flat()};  // a plane: lit as level ground
}

namespace {
inline float rayLength(double xc, double yc) noexcept { return static_cast<float>(std::sqrt(1.0 + xc * xc + yc * yc)); }

// A per-ray hit as the pixel shows it: its colour hazed at `rangeM`, or through a complex stick's
// see-through texel what the secondary ray sees (SeeThrough.h).
SeenThrough shadedHit(const CasterFrame& f, CasterThread& t, const RayLine& r, const MarchHit& h, const glm::dvec3& d,
                      double depth, float rangeM) noexcept {
  std::uint32_t texel = 0xFF000000u;
  const Rgb colour = hitColour(f, t, r, h, depth, f.seeThrough ? &texel : nullptr);
  if (seeThroughTexel(texel)) {
    TileWindows window;
    return seeThrough(f, t, d, depth, window);
  }
  return {f.shading.terrain(colour, rangeM), rangeM};
}

// Rays that missed the terrain in sub-rows q = qFrom ... qTo of the column at camera-space x `xc`:
// sky, or the base plane beyond the edge (a descending ray). A ray's world z and length are linear
// / quadratic in the camera-space yc of the row.
void castSkyRows(const CasterFrame& f, CasterThread& t, ColumnSink& sink, double xc, int qFrom, int qTo) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const CameraAxes& ax = f.geo->axes();
  const double invS = 1.0 / sink.s;
  const double az = xc * ax.right.z + ax.forward.z;
  for (int q = qFrom; q >= qTo; --q) {
    const double yc = (k.cyPx - (q + 0.5) * invS) / k.fyPx;
    float rangeM;
    const Rgb c = f.missed(az + yc * ax.up.z, rayLength(xc, yc), rangeM);
    sink.emit(q, c, rangeM);
  }
  t.rays += static_cast<std::uint64_t>(std::max(qFrom + 1 - qTo, 0));
}

// Per-ray casting of sub-rows q = qFrom, qFrom−1, ..., qTo (the rows the plane march cannot take:
// below the first hit, and beyond the terrain's edge). Stops after the first hit when `untilHit`.
// Returns the sub-row below which it stopped (−1 when it cast down to qTo; below qTo when the hit
// was on it) and the hit. The first
// ray starts at `resume` when given and it marches along the same major axis (its distance is then
// measured along the grid lines the plane march took; on the other axis the crossing's minor
// offset could put the start past terrain the ray has not been tested against).
int castRowsPerRay(const CasterFrame& f, CasterThread& t, ColumnSink& sink, double uc, int qFrom, bool untilHit,
                   bool& havePrev, glm::dvec2& prevHit, MarchHit& hitOut, RayLine& lineOut, int qTo,
                   const PlaneStop* resume = nullptr) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const double xc = (uc - k.cxPx) / k.fxPx;
  for (int q = qFrom; q >= qTo; --q) {
    const double vq = (q + 0.5) / f.supersample;
    const glm::dvec3 d = f.geo->ray(uc, vq);
    const float length = rayLength(xc, -(vq - k.cyPx) / k.fyPx);
    RayLine r;
    if (setupLine(f, d, r)) {
      if (q == qFrom && resume != nullptr && resume->valid && resume->xMajor == r.xMajor) {
        prevHit = resume->point;
        havePrev = true;
      }
      const MarchHit h = marchCoherent(f, t, r, havePrev, prevHit);
      if (h.hit) {
        const double depth = h.m / r.aMaj;
        const SeenThrough seen = shadedHit(f, t, r, h, d, depth, static_cast<float>(depth) * length);
        sink.emit(q, seen.colour, seen.rangeM);
        ++t.rays;
        if (untilHit) {
          hitOut = h;
          lineOut = r;
          return q - 1;
        }
        continue;
      }
      // Missed. An ascending ray passes over everything, and so does every ray above it. A
      // descending one left the terrain's side; the ray above starts where this one left (a
      // pitched column fans out in azimuth, so it may come back over the terrain: retrace).
      if (d.z >= 0.0) {
        castSkyRows(f, t, sink, xc, q, qTo);
        return -1;
      }
    } else {
      havePrev = false;  // nowhere near the terrain: the next ray starts afresh
    }
    float rangeM;
    const Rgb c = f.missed(d.z, length, rangeM);
    sink.emit(q, c, rangeM);
    ++t.rays;
  }
  return -1;
}

inline double finiteOrZero(double x) noexcept { return std::isfinite(x) ? x : 0.0; }

// One column being cast: the rays below its first hit, its plane march (which can pause at a
// depth, see castColumns) and the rows the march leaves.
class ColumnCast {
 public:
  // Column u casts the rows `rows` of the frame (its footprint's).
  ColumnCast(const CasterFrame& f, int u, RowRun rows, std::uint8_t* columnPixels, float* columnRanges) noexcept
      : mSink(f, f.supersample, columnPixels, columnRanges), mUc(u + 0.5), mRows(rows) {
    mSink.qTop = f.supersample * rows.first;
  }

  // The bottom rays, one by one until one hits (the first by descending the max pyramid).
  void castBottomRays(const CasterFrame& f, CasterThread& t) noexcept {
    mQ = castRowsPerRay(f, t, mSink, mUc, f.supersample * mRows.end - 1, true, mHavePrev, mPrevHit, mHit, mLine,
                        mSink.qTop);
    if (mQ < mSink.qTop) {
      mQ = -1;  // no ray hit, or the hit was on the column's top sub-row: done
      return;
    }
    mPlane = columnPlane(f, mUc);
    mDepth = finiteOrZero(mHit.m / mLine.aMaj);
  }

  bool done() const noexcept { return mQ < 0; }
  RowRun rows() const noexcept { return mRows; }
  // Depth of the last terrain the column saw (its march pauses past a depth). Finite: a column
  // castColumns could not order would never be marched.
  double depth() const noexcept { return mDepth; }

  // Marches the column until its crossings pass `pauseDepth`, or to its end; at the end casts the
  // rows the march left.
  void march(const CasterFrame& f, CasterThread& t, double pauseDepth, TileWindows& window) noexcept {
    const int q = marchPlane(f, t, mSink, mPlane, mQ, mPrevHit, mHit.at.level, mStopped, mMarch, pauseDepth, window);
    if (mMarch.paused) {
      mDepth = finiteOrZero(mMarch.crossings[mMarch.prev].depth);
      return;
    }
    castRowsLeft(f, t, q, mMarch.passedOver);
  }

  const ColumnPlane& plane() const noexcept { return mPlane; }
  // The column for a lane march (LaneMarch.h), which does its plane march in step with others.
  LaneColumn laneColumn() noexcept { return {&mSink, &mPlane, mQ, mPrevHit, mHit.at.level, {}, {}}; }
  // After its lane march: the rows it left.
  void finishLane(const CasterFrame& f, CasterThread& t, const LaneColumn& lane) noexcept {
    mStopped = lane.stopped;
    castRowsLeft(f, t, lane.q, lane.passedOver);
  }

 private:
  // The rows from q down that the plane march left (none when q is above the column's top
  // sub-row), and those it passed over;
  // the column is then done.
  void castRowsLeft(const CasterFrame& f, CasterThread& t, int q, const RowsPassedOver& passedOver) noexcept {
    mQ = -1;
    castRowsUnmarched(f, t, q);
    recastRowsPassedOver(f, t, passedOver);
  }

  void castRowsUnmarched(const CasterFrame& f, CasterThread& t, int q) noexcept {
    if (q < mSink.qTop) return;
    // Above all the terrain, the rows left see the sky. Otherwise (the march left the grid, or
    // could not start) they are cast one by one: a row may look over the terrain's edge and a
    // tilted column come back over it, and a row above the horizon may still meet a slope that
    // rises above the camera. The per-ray march ends the column with sky at the first climbing ray
    // that misses.
    if (mStopped.overTerrain) {
      castSkyRows(f, t, mSink, mPlane.xc, q, mSink.qTop);
      return;
    }
    castRowsPerRay(f, t, mSink, mUc, q, false, mHavePrev, mPrevHit, mHit, mLine, mSink.qTop, &mStopped);
  }

  // Rows whose rays meet terrain the plane march passed over (lookPastCrossing), cast ray by ray
  // over what the march gave them, whole pixels at a time (the sink averages a pixel's sub-rows).
  // Each ray from its own first hit in the max pyramid: the ray below may have seen terrain behind.
  void recastRowsPassedOver(const CasterFrame& f, CasterThread& t, const RowsPassedOver& rows) noexcept {
    const int s = mSink.s;
    for (int n = 0; n < rows.count; ++n) {
      const RowsPassedOver::Span& span = rows.spans[n];
      // Whole pixels of the column's run (beyond it the column repeats its end pixels)
      const int hi = std::min(span.hi / s * s + s - 1, s * mRows.end - 1);
      const int lo = std::max(span.lo / s * s, mSink.qTop);
      for (int q = hi; q >= lo; --q) {
        bool havePrev = false;
        glm::dvec2 prevHit{0.0};
        MarchHit hit;
        RayLine line;
        castRowsPerRay(f, t, mSink, mUc, q, false, havePrev, prevHit, hit, line, q);
      }
    }
  }

  ColumnSink mSink;
  double mUc;
  RowRun mRows;
  int mQ = -1;  // the sub-row the march started from (it resumes from its state); −1 once done
  bool mHavePrev = false;
  glm::dvec2 mPrevHit{0.0};
  MarchHit mHit;
  RayLine mLine;
  ColumnPlane mPlane;
  PlaneStop mStopped;
  PlaneMarchState mMarch;
  double mDepth = 0.0;
};

// Transposes `columns` staged columns of `rows` elements of Bytes each (column-major) into rows of
// `dst` (`stride` bytes apart). Bytes is a constant so each copy is a move or two.
template <std::size_t Bytes>
void transposeStaging(const std::uint8_t* src, std::size_t rows, std::size_t columns, std::uint8_t* dst,
                      std::size_t stride) noexcept {
  for (std::size_t v = 0; v < rows; ++v, dst += stride) {
    for (std::size_t c = 0; c < columns; ++c) std::memcpy(dst + c * Bytes, src + (c * rows + v) * Bytes, Bytes);
  }
}

// Copies `columns` staged columns (column-major, `rows` each) into the frame from column u0.
void flushStaging(const CasterFrame& f, const CasterThread& t, int u0, int columns, int rows) noexcept {
  const auto rowsZ = static_cast<std::size_t>(rows);
  const auto columnsZ = static_cast<std::size_t>(columns);
  if (f.image != nullptr) {
    const auto bpp = static_cast<std::size_t>(f.shading.bytesPerPixel());
    std::uint8_t* dst = f.image->bytes().data() + static_cast<std::size_t>(u0) * bpp;
    if (bpp == 3) {
      transposeStaging<3>(t.columnPixels.data(), rowsZ, columnsZ, dst, f.image->strideBytes());
    } else {
      transposeStaging<1>(t.columnPixels.data(), rowsZ, columnsZ, dst, f.image->strideBytes());
    }
  }
  if (f.rangeM != nullptr) {
    const auto width = static_cast<std::size_t>(f.geo->intrinsics().widthPx);
    transposeStaging<sizeof(float)>(reinterpret_cast<const std::uint8_t*>(t.columnRanges.data()), rowsZ, columnsZ,
                                    reinterpret_cast<std::uint8_t*>(f.rangeM + u0), width * sizeof(float));
  }
}

}  // namespace

void castColumns(const CasterFrame& f, int u0, int u1, CasterThread& t) noexcept {
  // The columns are cast into a column-major staging block and copied into the frame a block at a
  // time. The caster then writes each pixel next to the last instead of into a new image row, and
  // two workers on neighbouring columns do not write the same cache lines pixel by pixel: that
  // false sharing cost the second worker a third of its gain.
  const int rows = f.geo->intrinsics().heightPx;
  const auto bpp = static_cast<std::size_t>(f.shading.bytesPerPixel());
  const auto staged = static_cast<std::size_t>(CasterThread::kStagingColumns) * static_cast<std::size_t>(rows);
  if (f.image != nullptr && t.columnPixels.size() < staged * bpp) t.columnPixels.resize(staged * bpp);
  if (f.rangeM != nullptr && t.columnRanges.size() < staged) t.columnRanges.resize(staged);
  for (int b0 = u0; b0 < u1; b0 += CasterThread::kStagingColumns) {
    const int b1 = std::min(u1, b0 + CasterThread::kStagingColumns);
    // The block's columns march in step, one depth band after another: their crossings lie on the
    // same grid lines, so all but the first read heights and texels already in L1 (one column's
    // whole march reads more lines than L1 holds).
    std::array<std::optional<ColumnCast>, CasterThread::kStagingColumns> block;
    TileWindows window;                                        // the tiles the block's marches read last, one per level
    double nearest = std::numeric_limits<double>::infinity();  // depth of the column furthest behind
    for (int u = b0; u < b1; ++u) {
      const auto c = static_cast<std::size_t>(u - b0) * static_cast<std::size_t>(rows);
      ColumnCast& column = block[static_cast<std::size_t>(u - b0)].emplace(
          f, u, f.footprint.rows(u), t.columnPixels.data() + c * bpp, t.columnRanges.data() + c);
      column.castBottomRays(f, t);
      if (!column.done()) nearest = std::min(nearest, column.depth());
    }
    if (f.laneMarch) {
      // In lane blocks of kLaneColumns: the columns of a block that share the first one's major
      // axis and direction march in step (LaneMarch.h); any other goes on to the depth bands below
      nearest = std::numeric_limits<double>::infinity();
      for (int g = 0; g < b1 - b0; g += kLaneColumns) {
        std::array<LaneColumn, kLaneColumns> lanes;
        std::array<ColumnCast*, kLaneColumns> laneOf{};
        int count = 0;
        const ColumnPlane* first = nullptr;
        for (int u = g; u < std::min(g + kLaneColumns, b1 - b0); ++u) {
          std::optional<ColumnCast>& column = block[static_cast<std::size_t>(u)];
          if (!column || column->done()) continue;
          if (first == nullptr) first = &column->plane();
          if (column->plane().xMajor != first->xMajor || column->plane().sx != first->sx) {
            nearest = std::min(nearest, column->depth());
            continue;
          }
          lanes[static_cast<std::size_t>(count)] = column->laneColumn();
          laneOf[static_cast<std::size_t>(count++)] = &*column;
        }
        marchLanes(f, t, std::span(lanes.data(), static_cast<std::size_t>(count)), window);
        for (int n = 0; n < count; ++n)
          laneOf[static_cast<std::size_t>(n)]->finishLane(f, t, lanes[static_cast<std::size_t>(n)]);
      }
    }
    while (nearest < std::numeric_limits<double>::infinity()) {
      const double pause = nearest * std::max(f.marchBand, 1.0);  // ≥ nearest: the nearest column moves on
      nearest = std::numeric_limits<double>::infinity();
      for (std::optional<ColumnCast>& column : block) {
        if (!column || column->done()) continue;
        column->march(f, t, pause, window);
        if (!column->done()) nearest = std::min(nearest, column->depth());
      }
    }
    for (int u = b0; u < b1; ++u) {
      const auto c = static_cast<std::size_t>(u - b0) * static_cast<std::size_t>(rows);
      repeatColumnEnds(f.image != nullptr ? t.columnPixels.data() + c * bpp : nullptr, bpp, bpp,
                       f.rangeM != nullptr ? t.columnRanges.data() + c : nullptr, 1, rows,
                       block[static_cast<std::size_t>(u - b0)]->rows());
    }
    flushStaging(f, t, b0, b1 - b0, rows);
  }
}

void castColumnsPerRay(const CasterFrame& f, int u0, int u1, CasterThread& t) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const int s = f.supersample;
  const float scale = 1.0f / static_cast<float>(s);
  for (int u = u0; u < u1; ++u) {
    const double uc = u + 0.5;
    bool sky = false;
    bool havePrev = false;
    glm::dvec2 prevHit{0.0};  // level-0 units of the ray below's hit
    const RowRun run = f.footprint.rows(u);
    for (int v = run.end - 1; v >= run.first; --v) {
      Rgb sum;
      float rangePx = std::numeric_limits<float>::infinity();
      for (int sub = s - 1; sub >= 0; --sub) {
        const glm::dvec3 d = f.geo->ray(uc, v + (sub + 0.5) / s);
        const double length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        ++t.rays;
        RayLine r;
        if (!sky && setupLine(f, d, r)) {
          const MarchHit h = marchCoherent(f, t, r, havePrev, prevHit);
          if (h.hit) {
            const double depth = h.m / r.aMaj;
            const SeenThrough seen = shadedHit(f, t, r, h, d, depth, static_cast<float>(depth * length));
            sum += seen.colour;
            if (sub == s / 2) rangePx = seen.rangeM;
            continue;
          }
          // Missed. An ascending ray passes over everything, and so does every ray above it. A
          // descending one left the terrain's side; the ray above starts where this one left (a
          // pitched column fans out in azimuth, so it may come back over the terrain: retrace).
          if (d.z >= 0.0) sky = true;
        } else {
          havePrev = false;  // nowhere near the terrain: the next ray starts afresh
        }
        float rangeM;
        sum += f.missed(d.z, length, rangeM);
        if (sub == s / 2) rangePx = rangeM;
      }
      if (f.image != nullptr) f.shading.store(f.image->row(v), u, sum, scale);
      if (f.rangeM != nullptr)
        f.rangeM[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.widthPx) + u] = rangePx;
    }
    const std::size_t bpp = f.image != nullptr ? static_cast<std::size_t>(f.shading.bytesPerPixel()) : 0;
    repeatColumnEnds(f.image != nullptr ? f.image->bytes().data() + static_cast<std::size_t>(u) * bpp : nullptr, bpp,
                     f.image != nullptr ? f.image->strideBytes() : 0, f.rangeM != nullptr ? f.rangeM + u : nullptr,
                     static_cast<std::size_t>(k.widthPx), k.heightPx, run);
  }
}

namespace {

// The crossing of the ray eye + t·d (descending) with the bilinear surface of `level` between
// depths tLo (above it) and tHi (below it), by bisection: for a ray that moves less than a voxel
// or two sideways there, where the surface under it is single-valued. False when tLo is not above.
bool bisectSurface(const CasterFrame& f, const glm::dvec3& d, double tLo, double tHi, int level,
                   CastResult& out) noexcept {
  const TerrainGeometry& g = f.view->geometry();
  const glm::dvec3 eye = f.geo->pose().positionM;
  const auto above = [&](double depth) {
    const glm::dvec3 p = eye + depth * d;
    return p.z > f.view->heightAtM(p.x, p.y, level);
  };
  if (!above(tLo) || above(tHi)) return false;
  for (int k = 0; k < 48; ++k) {
    const double mid = 0.5 * (tLo + tHi);
    (above(mid) ? tLo : tHi) = mid;
  }
  out.hit = true;
  out.depthM = tHi;
  out.level = level;
  out.pointM = eye + tHi * d;
  // The level's voxel whose area holds the point (voxel j's centre: origin + ((j + ½)·2^L − ½)·spacing)
  const auto voxel = [&](double offsetM) {
    return static_cast<int>(std::floor((offsetM / g.spacingM + 0.5) / static_cast<double>(1 << level)));
  };
  out.colour = f.view->sample(level, voxel(out.pointM.x - g.originM.x), voxel(out.pointM.y - g.originM.y)).colour;
  return true;
}

// A descending ray whose base-plane point lies over the grid meets the terrain (it is above the
// base plane everywhere). One too steep to cross a grid line on the way (looking straight down)
// gives the line march nothing to test: its hit between the terrain's ceiling and the base plane.
bool steepHit(const CasterFrame& f, const glm::dvec3& d, CastResult& out) noexcept {
  if (!(d.z < 0.0) || !(f.baseAboveM > 0.0)) return false;
  const TerrainGeometry& g = f.view->geometry();
  const double tBase = f.baseAboveM / -d.z;
  const glm::dvec3 base = f.geo->pose().positionM + tBase * d;
  const bool overGrid = base.x >= g.originM.x && base.y >= g.originM.y &&
                        base.x <= g.originM.x + (g.widthVox - 1) * g.spacingM &&
                        base.y <= g.originM.y + (g.heightVox - 1) * g.spacingM;
  if (!overGrid) return false;
  const double tCeiling = std::max(0.0, (f.baseAboveM - f.ceilingQ / f.quantaPerM) / -d.z);
  return bisectSurface(f, d, tCeiling, tBase, f.geo->lodLevel(0.5 * (tCeiling + tBase), d), out);
}

}  // namespace

CastResult castRay(const CasterFrame& f, double u, double v, CasterThread& t) noexcept {
  const glm::dvec3 d = f.geo->ray(u, v);
  RayLine r;
  CastResult out;
  const MarchHit h = setupLine(f, d, r) ? ray_march::march(f, t, r, firstHitStart(f, r)) : MarchHit{};
  if (!h.hit && steepHit(f, d, out)) return out;
  // A steep ray whose first grid line is already below the surface retraces back to where it
  // entered the terrain's height slab and stops there, at the ceiling: the crossing lies between
  // that entry and the line
  if (h.hit && h.m <= r.mEnter && d.z < 0.0) {
    const double tLo = r.mEnter / r.aMaj, tHi = lineM(r, h.at.i, h.at.level) / r.aMaj;
    const int level = f.geo->lodLevel(tHi, d);
    // Only where the ray moves less than two of that level's voxels sideways in between (so the
    // crossing found is the first); otherwise the line march's answer stands
    const double sideways = std::hypot(d.x, d.y) * (tHi - tLo);
    const double cell = f.view->geometry().spacingM * static_cast<double>(1 << level);
    if (sideways < 2.0 * cell && bisectSurface(f, d, tLo, tHi, level, out)) return out;
  }
  if (!h.hit) {
    // The base plane beyond the edge is a surface too (the warp fits to it), or the sky.
    const double rangeM = basePlaneRangeM(f.baseAboveM, d.z, glm::length(d));
    if (!std::isfinite(rangeM)) return out;
    out.hit = true;
    out.depthM = rangeM / glm::length(d);
    out.level = f.geo->lodLevel(out.depthM, d);
    out.pointM = f.geo->pose().positionM + out.depthM * d;
    out.colour = f.baseColourRgba;
    return out;
  }
  out.hit = true;
  out.level = h.at.level;
  out.depthM = h.m / r.aMaj;
  out.pointM = worldPoint(f, r, h.m);
  const int j = static_cast<int>(h.at.y >> 32);
  out.colour = r.xMajor ? colourAt(f, t, h.at.level, h.at.i, j) : colourAt(f, t, h.at.level, j, h.at.i);
  return out;
}

}  // namespace fieldcast::core
