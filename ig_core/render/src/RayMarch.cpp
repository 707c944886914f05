// The per-ray march (RayMarch.h), one ray at a time, each starting where the ray below it hit:
// vertical ray coherence after Cohen-Or, Rich, Lerner, Shenkar ("A real-time photo-realistic
// visual flythrough", 1996); backward retrace after Wan, Qu & Kaufman (2000).
#include "RayMarch.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace fieldcast::core::ray_march {
namespace {

constexpr double kMinorOne = 4294967296.0;  // 2^32: minor index fixed point
constexpr double kZOne = 65536.0;           // 2^16: height fixed point
constexpr int kNoIndex = std::numeric_limits<int>::min() / 2;

// ceil(log2(m / mUnit)) clamped to the pyramid, read off the double's exponent and mantissa bits.
inline int levelAt(const CasterFrame& f, const RayLine& r, double m) noexcept {
  const double ratio = m * r.invMUnit;
  if (!(ratio > 1.0)) return 0;
  const auto bits = std::bit_cast<std::uint64_t>(ratio);
  const int exponent = static_cast<int>(bits >> 52) - 1023;  // ratio = 1.mantissa · 2^exponent
  const int level = exponent + ((bits & ((std::uint64_t{1} << 52) - 1)) != 0 ? 1 : 0);
  return std::min(level, f.levels - 1);
}

// Level-0 major coordinate of level-L grid line i, and its m.
inline double lineCoord(int i, int level) noexcept { return (i + 0.5) * pow2(level) - 0.5; }
inline double mAt(const RayLine& r, int i, int level) noexcept { return r.sx * (lineCoord(i, level) - r.cMaj); }

// Grid line of `level` at or before m (in the march direction).
int lineAtOrBefore(const RayLine& r, double m, int level) noexcept {
  const double xl = levelIndex(r.cMaj + r.sx * m, level);
  return r.sx > 0 ? floorToInt(xl) : ceilToInt(xl);
}

Cursor cursorAt(const RayLine& r, int level, int i) noexcept {
  const double m = mAt(r, i, level);
  Cursor c;
  c.level = level;
  c.i = i;
  c.y = floorToInt64(levelIndex(r.cMin + r.slope * m, level) * kMinorOne);
  c.z = floorToInt64(r.zPer * m * kZOne);
  return c;
}

// Surface height (quanta 48.16) under the cursor, along the grid line, by the generic path.
std::int64_t surfaceAt(const CasterFrame& f, CasterThread& t, const RayLine& r, const Cursor& c) noexcept {
  const int j = static_cast<int>(c.y >> 32);
  const std::int64_t frac = static_cast<std::uint32_t>(c.y) >> 16;
  const std::int64_t h0 = r.xMajor ? heightAt(f, t, c.level, c.i, j) : heightAt(f, t, c.level, j, c.i);
  const std::int64_t h1 = r.xMajor ? heightAt(f, t, c.level, c.i, j + 1) : heightAt(f, t, c.level, j + 1, c.i);
  ++t.steps;
  ++t.generic;
  return (h0 << 16) + (h1 - h0) * frac;
}

MarchHit makeHit(const RayLine& r, const Cursor& at, std::int64_t diff, double prevM, std::int64_t prevDiff) noexcept {
  const double mHere = mAt(r, at.i, at.level);
  const double denom = static_cast<double>(prevDiff - diff);
  const double phi = denom > 0.0 ? static_cast<double>(prevDiff) / denom : 1.0;
  return MarchHit{true, at, prevM + phi * (mHere - prevM)};
}

enum class RunEnd : std::uint8_t { Hit, Stop, LeftTile };

// The inner loop: steps grid line by grid line through one tile at one level until iStop, a hit,
// or the minor row pair leaving the tile. Two loads, a multiply and a compare per step.
template <bool kXMajor>
RunEnd fastRun(Cursor& c, int sx, int iStop, std::int64_t dy, std::int64_t dz, const std::uint16_t* tileHeights,
               int tileShift, int jBase, int iBase, std::int64_t& prevDiff, std::int64_t& hitDiff,
               std::uint64_t& steps) noexcept {
  const unsigned rowPairLimit = (1u << tileShift) - 1u;  // j and j+1 both inside the tile
  const std::ptrdiff_t minorStride = kXMajor ? (std::ptrdiff_t{1} << tileShift) : 1;
  const std::ptrdiff_t majorStride = kXMajor ? 1 : (std::ptrdiff_t{1} << tileShift);
  const std::uint16_t* line = tileHeights + (c.i - iBase) * majorStride;
  const std::ptrdiff_t lineStep = sx * majorStride;
  std::int64_t y = c.y;
  std::int64_t z = c.z;
  int i = c.i;
  std::uint64_t n = 0;
  RunEnd end = RunEnd::Stop;
  for (; i != iStop; i += sx, line += lineStep, y += dy, z += dz) {
    const unsigned j = static_cast<unsigned>(static_cast<int>(y >> 32) - jBase);
    if (j >= rowPairLimit) {
      end = RunEnd::LeftTile;
      break;
    }
    const std::uint16_t* p = line + static_cast<std::ptrdiff_t>(j) * minorStride;
    const std::int64_t h0 = p[0];
    const std::int64_t h1 = p[minorStride];
    const std::int64_t frac = static_cast<std::uint32_t>(y) >> 16;
    const std::int64_t diff = z - ((h0 << 16) + (h1 - h0) * frac);
    ++n;
    if (diff <= 0) {
      hitDiff = diff;
      end = RunEnd::Hit;
      break;
    }
    prevDiff = diff;
  }
  steps += n;
  c.i = i;
  c.y = y;
  c.z = z;
  return end;
}

// Per-level stop indices of one ray: where the march switches to the next level (on an even
// step, so the next level's grid line is half a step ahead) and where it leaves the terrain.
struct LevelStops {
  int level = -1;
  int iSwitch = kNoIndex;
  int iExit = kNoIndex;
};

LevelStops stopsFor(const CasterFrame& f, const RayLine& r, int level) noexcept {
  LevelStops s;
  s.level = level;
  const double exitIndex = levelIndex(r.cMaj + r.sx * r.mExit, level);
  const double lim = 1e9;
  s.iExit = r.sx > 0 ? floorToInt(std::min(exitIndex, lim)) + 1 : ceilToInt(std::max(exitIndex, -lim)) - 1;
  if (level + 1 < f.levels) {
    const double switchIndex = levelIndex(r.cMaj + r.sx * r.mUnit * pow2(level), level);
    if (r.sx > 0) {
      int i = ceilToInt(std::min(switchIndex, lim));
      if (i & 1) ++i;
      s.iSwitch = i;
    } else {
      int i = floorToInt(std::max(switchIndex, -lim));
      if (!(i & 1)) --i;
      s.iSwitch = i;
    }
  }
  return s;
}

constexpr std::int64_t kNoSample = std::numeric_limits<std::int64_t>::max();

// The start sample lay below the surface (the ray below saw a slightly different slice of the
// terrain): walk back grid line by grid line to the last point above it.
MarchHit retrace(const CasterFrame& f, CasterThread& t, const RayLine& r, Cursor c, std::int64_t diff,
                 std::int64_t camZ) noexcept {
  ++t.retraces;
  for (int back = 0; back < (1 << 20); ++back) {
    const double mBack = mAt(r, c.i - r.sx, c.level);
    if (mBack < r.mEnter) return MarchHit{true, c, std::max(r.mEnter, 0.0)};
    Cursor b = cursorAt(r, c.level, c.i - r.sx);
    b.z += camZ;
    const std::int64_t bDiff = b.z - surfaceAt(f, t, r, b);
    if (bDiff > 0) return makeHit(r, c, diff, mBack, bDiff);
    c = b;
    diff = bDiff;
  }
  return MarchHit{true, c, mAt(r, c.i, c.level)};
}

}  // namespace

// The functions RayMarch.h declares, in its order.

double lineM(const RayLine& r, int i, int level) noexcept { return mAt(r, i, level); }

bool setupLine(const CasterFrame& f, const glm::dvec3& d, RayLine& r) noexcept {
  const double dx = d.x * f.unitsPerM;
  const double dy = d.y * f.unitsPerM;
  r.xMajor = std::abs(dx) >= std::abs(dy);
  const double dMaj = r.xMajor ? dx : dy;
  const double dMin = r.xMajor ? dy : dx;
  r.sx = dMaj >= 0.0 ? 1 : -1;
  // Nearly vertical rays: bound the height change per unit of m (so the fixed point cannot
  // overflow) by treating the ray as very slightly tilted; the hit moves by < 0.01 voxel.
  r.aMaj = std::max({std::abs(dMaj), std::abs(d.z) * f.quantaPerM * 1e-7, 1e-12});
  r.cMaj = r.xMajor ? f.camX : f.camY;
  r.cMin = r.xMajor ? f.camY : f.camX;
  const double inv = 1.0 / r.aMaj;
  r.slope = dMin * inv;
  r.zPer = d.z * f.quantaPerM * inv;
  r.lodStretch = f.geo->lodStretch(d);
  r.mUnit = f.geo->lodDepth0M() * r.aMaj / r.lodStretch;
  r.invMUnit = 1.0 / r.mUnit;

  const double majSize = (r.xMajor ? f.levelWidth[0] : f.levelHeight[0]) - 1;
  const double minSize = (r.xMajor ? f.levelHeight[0] : f.levelWidth[0]) - 1;
  // Major axis slab [0, majSize].
  double lo = r.sx > 0 ? -r.cMaj : r.cMaj - majSize;
  double hi = r.sx > 0 ? majSize - r.cMaj : r.cMaj;
  // Minor axis slab [0, minSize].
  if (r.slope != 0.0) {
    const double a = (0.0 - r.cMin) / r.slope;
    const double b = (minSize - r.cMin) / r.slope;
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  } else if (r.cMin < 0.0 || r.cMin > minSize) {
    return false;
  }
  // Height slab: below the highest terrain point ...
  const double above = f.camZq - f.ceilingQ;
  if (r.zPer < 0.0) {
    lo = std::max(lo, above / -r.zPer);
    // ... and above the base plane (quantised height 0, below all terrain; half a quantum lower
    // so no terrain hit is clipped): seen from outside, the grid's sides end there.
    hi = std::min(hi, (f.camZq + 0.5) / -r.zPer);
  } else if (above > 0.0) {
    return false;
  } else if (r.zPer > 0.0) {
    hi = std::min(hi, -above / r.zPer);
  }
  r.mEnter = std::max(lo, 0.0);
  r.mExit = hi;
  return r.mEnter <= r.mExit;
}

[[gnu::noinline]] const TerrainTile* tileAt(const CasterFrame& f, CasterThread& t, int level, int tx, int ty) noexcept {
  CasterThread::CachedTile& c = t.tiles[static_cast<std::size_t>(level)];
  if (c.tx == tx && c.ty == ty) return c.tile;
  const TerrainGeometry& g = f.view->geometry();
  const TerrainTile* tile = nullptr;
  if (tx >= 0 && ty >= 0 && tx < g.tilesX(level) && ty < g.tilesY(level)) tile = f.view->tile(level, tx, ty);
  c = CasterThread::CachedTile{tx, ty, tile};
  return tile;
}

std::uint16_t heightAt(const CasterFrame& f, CasterThread& t, int level, int x, int y) noexcept {
  x = std::clamp(x, 0, f.levelWidth[static_cast<std::size_t>(level)] - 1);
  y = std::clamp(y, 0, f.levelHeight[static_cast<std::size_t>(level)] - 1);
  const TerrainTile* tile = tileAt(f, t, level, x >> f.tileShift, y >> f.tileShift);
  if (tile == nullptr) return f.view->heightQ(level, x, y);
  return tile->heightQ[((y & f.tileMask) << f.tileShift) | (x & f.tileMask)];
}
std::uint32_t colourAt(const CasterFrame& f, CasterThread& t, int level, int x, int y) noexcept {
  x = std::clamp(x, 0, f.levelWidth[static_cast<std::size_t>(level)] - 1);
  y = std::clamp(y, 0, f.levelHeight[static_cast<std::size_t>(level)] - 1);
  const TerrainTile* tile = tileAt(f, t, level, x >> f.tileShift, y >> f.tileShift);
  if (tile == nullptr) return f.view->colourRgba(level, x, y);
  return tile->colourRgba[((y & f.tileMask) << f.tileShift) | (x & f.tileMask)];
}

float segmentLight(const CasterFrame& f, CasterThread& t, int level, int x, int y, bool alongX, float phi) noexcept {
  // Along the segment: the voxel before it, its two voxels, the one after; beside each of its two
  // voxels, the one below and the one above across it. From one tile when they lie in it (most
  // do), else one by one.
  const int ax = alongX ? 1 : 0, ay = alongX ? 0 : 1;  // along
  const int ux = ay, uy = ax;                          // across
  float before, h0, h1, after, below0, below1, above0, above1;
  const int lx = x & f.tileMask, ly = y & f.tileMask;
  const TerrainTile* tile = nullptr;
  if (lx > 0 && lx + 2 < f.tileMask && ly > 0 && ly + 2 < f.tileMask && x > 0 && y > 0 &&
      x + 2 < f.levelWidth[static_cast<std::size_t>(level)] && y + 2 < f.levelHeight[static_cast<std::size_t>(level)]) {
    tile = tileAt(f, t, level, x >> f.tileShift, y >> f.tileShift);
  }
  if (tile != nullptr) {
    const std::ptrdiff_t row = std::ptrdiff_t{1} << f.tileShift;
    const std::uint16_t* p = tile->heightQ + ((ly << f.tileShift) | lx);
    const std::ptrdiff_t along = ay * row + ax, across = uy * row + ux;
    before = p[-along], h0 = p[0], h1 = p[along], after = p[2 * along];
    below0 = p[-across], below1 = p[along - across], above0 = p[across], above1 = p[along + across];
  } else {
    const auto h = [&](int dx, int dy) { return static_cast<float>(heightAt(f, t, level, x + dx, y + dy)); };
    before = h(-ax, -ay), h0 = h(0, 0), h1 = h(ax, ay), after = h(2 * ax, 2 * ay);
    below0 = h(-ux, -uy), below1 = h(ax - ux, ay - uy), above0 = h(ux, uy), above1 = h(ax + ux, ay + uy);
  }
  // Quanta per voxel step to metres per metre at this level.
  const auto scale = static_cast<float>(1.0 / (f.quantaPerM * pow2(level)) * f.unitsPerM);
  const TerrainLight& light = f.shading.light();
  const auto factor = [&](float along, float across) {
    return alongX ? light.terrain(along * scale, across * scale) : light.terrain(across * scale, along * scale);
  };
  const float l0 = factor(minmodSlope(h0 - before, h1 - h0), minmodSlope(h0 - below0, above0 - h0));
  const float l1 = factor(minmodSlope(h1 - h0, after - h1), minmodSlope(h1 - below1, above1 - h1));
  return l0 + (l1 - l0) * phi;
}

StickVoxel stickAt(const CasterFrame& f, CasterThread& t, int level, int x, int y) noexcept {
  if (f.sticks == nullptr) return {};
  x = std::clamp(x, 0, f.levelWidth[static_cast<std::size_t>(level)] - 1);
  y = std::clamp(y, 0, f.levelHeight[static_cast<std::size_t>(level)] - 1);
  const TerrainTile* tile = tileAt(f, t, level, x >> f.tileShift, y >> f.tileShift);
  if (tile == nullptr) {
    const TerrainView::Sample s = f.view->sample(level, x, y);
    return s.stickId != 0 ? StickVoxel{s.stickId, s.heightQ, s.level} : StickVoxel{};
  }
  if (tile->stickId == nullptr) return {};
  const auto index = static_cast<std::size_t>(((y & f.tileMask) << f.tileShift) | (x & f.tileMask));
  if (!tile->hasStick(index)) return {};
  const std::uint32_t id = tile->stickId[index];
  return id != 0 ? StickVoxel{id, tile->heightQ[index], level} : StickVoxel{};
}

MarchHit march(const CasterFrame& f, CasterThread& t, const RayLine& r, double mStart) noexcept {
  mStart = std::clamp(mStart, r.mEnter, r.mExit);
  int level = levelAt(f, r, mStart);
  int i = lineAtOrBefore(r, mStart, level);
  if (mAt(r, i, level) < r.mEnter) i += r.sx;
  const MarchHit miss{false, Cursor{}, r.mExit};
  const std::int64_t camZ = floorToInt64(f.camZq * kZOne);
  std::int64_t prevDiff = kNoSample;  // no sample yet: a first sample below the surface retraces
  double prevM = 0.0;
  LevelStops stops;
  for (;;) {
    if (stops.level != level) stops = stopsFor(f, r, level);
    if ((i - stops.iExit) * r.sx >= 0) return miss;
    if (i == stops.iSwitch) {
      // Even step reached: continue on the coarser level, whose grid line is half a step ahead.
      ++level;
      i >>= 1;
      continue;
    }
    const int tileEnd = r.sx > 0 ? ((i >> f.tileShift) + 1) << f.tileShift : ((i >> f.tileShift) << f.tileShift) - 1;
    int iStop = tileEnd;
    if (r.sx > 0) {
      iStop = std::min(iStop, stops.iExit);
      if (stops.iSwitch != kNoIndex) iStop = std::min(iStop, stops.iSwitch);
    } else {
      iStop = std::max(iStop, stops.iExit);
      if (stops.iSwitch != kNoIndex) iStop = std::max(iStop, stops.iSwitch);
    }
    Cursor c = cursorAt(r, level, i);
    c.z += camZ;
    const int j = static_cast<int>(c.y >> 32);
    const int majorTile = i >> f.tileShift;
    const int minorTile = j >> f.tileShift;
    const TerrainTile* tile = (j < 0)    ? nullptr
                              : r.xMajor ? tileAt(f, t, level, majorTile, minorTile)
                                         : tileAt(f, t, level, minorTile, majorTile);
    if (tile != nullptr && (j & f.tileMask) != f.tileMask) {
      const std::int64_t dy = floorToInt64(r.slope * kMinorOne);
      const std::int64_t dz = floorToInt64(r.zPer * pow2(level) * kZOne);
      const int runStart = i;
      ++t.runs;
      const bool hadSample = prevDiff != kNoSample;
      std::int64_t hitDiff = 0;
      const RunEnd end =
          r.xMajor ? fastRun<true>(c, r.sx, iStop, dy, dz, tile->heightQ, f.tileShift, minorTile << f.tileShift,
                                   majorTile << f.tileShift, prevDiff, hitDiff, t.steps)
                   : fastRun<false>(c, r.sx, iStop, dy, dz, tile->heightQ, f.tileShift, minorTile << f.tileShift,
                                    majorTile << f.tileShift, prevDiff, hitDiff, t.steps);
      if (c.i != runStart) prevM = mAt(r, c.i - r.sx, level);
      if (end == RunEnd::Hit) {
        if (c.i == runStart && !hadSample) return retrace(f, t, r, c, hitDiff, camZ);
        return makeHit(r, c, hitDiff, prevM, prevDiff);
      }
      i = c.i;
      if (end == RunEnd::Stop) continue;
      c = cursorAt(r, level, i);  // the row pair left the tile: one generic step below
      c.z += camZ;
    }
    // Generic step: the row pair straddles tiles, or the tile is missing (coarser fallback).
    const std::int64_t diff = c.z - surfaceAt(f, t, r, c);
    if (diff <= 0) {
      if (prevDiff == kNoSample) return retrace(f, t, r, c, diff, camZ);
      return makeHit(r, c, diff, prevM, prevDiff);
    }
    prevDiff = diff;
    prevM = mAt(r, i, level);
    i += r.sx;
  }
}

double firstHitStart(const CasterFrame& f, const RayLine& r) noexcept {
  double m = r.mEnter;
  int k = f.levels - 1;
  for (int iteration = 0; iteration < 4096; ++iteration) {
    if (m > r.mExit) return m;
    const int lod = levelAt(f, r, m);
    k = std::max(k, lod);
    const double cellSize = pow2(k);
    const double xMaj = r.cMaj + r.sx * m;
    const double xMin = r.cMin + r.slope * m;
    const int ci = floorToInt((xMaj + 0.5) / cellSize);
    const int cj = floorToInt((xMin + 0.5) / cellSize);
    // Where the ray leaves this cell.
    const double majEdge = r.sx > 0 ? (ci + 1) * cellSize - 0.5 : ci * cellSize - 0.5;
    double mOut = r.sx * (majEdge - r.cMaj);
    if (r.slope > 0.0) mOut = std::min(mOut, ((cj + 1) * cellSize - 0.5 - r.cMin) / r.slope);
    if (r.slope < 0.0) mOut = std::min(mOut, (cj * cellSize - 0.5 - r.cMin) / r.slope);
    mOut = std::min(mOut, r.mExit);
    const double zLow = f.camZq + r.zPer * (r.zPer < 0.0 ? mOut : m);
    const int cx = r.xMajor ? ci : cj;
    const int cy = r.xMajor ? cj : ci;
    const double maxQ = f.view->maxHeightQ(k, cx, cy);
    if (zLow > maxQ && k >= levelAt(f, r, mOut)) {
      m = mOut + 1e-9 * (1.0 + mOut);  // past the cell boundary
      k = std::min(k + 1, f.levels - 1);
      continue;
    }
    if (k > lod) {
      --k;
      continue;
    }
    return m;
  }
  return m;
}

MarchHit marchCoherent(const CasterFrame& f, CasterThread& t, const RayLine& r, bool& havePrev,
                       glm::dvec2& prevHit) noexcept {
  const double mStart =
      havePrev ? r.sx * ((r.xMajor ? prevHit.x : prevHit.y) - r.cMaj) : (++t.firstHits, firstHitStart(f, r));
  const MarchHit h = march(f, t, r, mStart);
  const double maj = r.cMaj + r.sx * h.m;
  const double min = r.cMin + r.slope * h.m;
  prevHit = r.xMajor ? glm::dvec2{maj, min} : glm::dvec2{min, maj};
  havePrev = true;
  return h;
}

Rgb hitColour(const CasterFrame& f, CasterThread& t, const RayLine& r, const MarchHit& h, double depthM,
              std::uint32_t* stickTexelOut) noexcept {
  const Cursor& c = h.at;
  const int j = static_cast<int>(c.y >> 32);
  const float frac = static_cast<float>(static_cast<std::uint32_t>(c.y) * (1.0 / kMinorOne));
  if (f.sticks != nullptr) {
    const StickVoxel s = r.xMajor ? colouringStick(stickAt(f, t, c.level, c.i, j), stickAt(f, t, c.level, c.i, j + 1))
                                  : colouringStick(stickAt(f, t, c.level, j, c.i), stickAt(f, t, c.level, j + 1, c.i));
    if (s.id != 0) {
      const double zQ = f.camZq + r.zPer * h.m;
      const std::uint32_t texel =
          stickTexel(f.sticks->texels(s.id, s.level), stickTexelCoordinate(s, zQ, f.stickUnitsPerQ));
      if (stickTexelOut != nullptr) *stickTexelOut = texel;
      return Rgb{unpackRgb(texel).v * f.shading.light().flat()};
    }
  }
  const std::uint32_t c0 = r.xMajor ? colourAt(f, t, c.level, c.i, j) : colourAt(f, t, c.level, j, c.i);
  const std::uint32_t c1 = r.xMajor ? colourAt(f, t, c.level, c.i, j + 1) : colourAt(f, t, c.level, j + 1, c.i);
  Rgb colour = mix(unpackRgb(c0), unpackRgb(c1), frac);
  const double w = f.blend ? f.geo->levelBlend(depthM * r.lodStretch, c.level) : 0.0;
  if (w > 0.0) {
    // The same point on the next level: continuous index there, bilinear over four voxels.
    const int up = c.level + 1;
    const double xMaj = lineCoord(c.i, c.level);
    const double xMin = (static_cast<double>(c.y) / kMinorOne + 0.5) * pow2(c.level) - 0.5;
    const double ux = levelIndex(r.xMajor ? xMaj : xMin, up);
    const double uy = levelIndex(r.xMajor ? xMin : xMaj, up);
    const int x0 = floorToInt(ux);
    const int y0 = floorToInt(uy);
    const auto fx = static_cast<float>(ux - x0);
    const auto fy = static_cast<float>(uy - y0);
    const Rgb a = mix(unpackRgb(colourAt(f, t, up, x0, y0)), unpackRgb(colourAt(f, t, up, x0 + 1, y0)), fx);
    const Rgb b = mix(unpackRgb(colourAt(f, t, up, x0, y0 + 1)), unpackRgb(colourAt(f, t, up, x0 + 1, y0 + 1)), fx);
    colour = mix(colour, mix(a, b, fy), static_cast<float>(w));
  }
  if (f.shading.light().relit()) {
    // The segment runs along the minor axis: north on an x-major line, else east.
    colour.v *=
        r.xMajor ? segmentLight(f, t, c.level, c.i, j, false, frac) : segmentLight(f, t, c.level, j, c.i, true, frac);
  }
  return colour;
}

glm::dvec3 worldPoint(const CasterFrame& f, const RayLine& r, double m) noexcept {
  const double maj = r.cMaj + r.sx * m;
  const double min = r.cMin + r.slope * m;
  const TerrainGeometry& g = f.view->geometry();
  const double x = r.xMajor ? maj : min;
  const double y = r.xMajor ? min : maj;
  return {g.originM.x + x * g.spacingM, g.originM.y + y * g.spacingM,
          g.heightBaseM + (f.camZq + r.zPer * m) / f.quantaPerM};
}

}  // namespace fieldcast::core::ray_march
