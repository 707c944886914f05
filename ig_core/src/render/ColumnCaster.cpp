// Column ray casting with vertical ray coherence (Cohen-Or, Rich, Lerner, Shenkar: "A real-time
// photo-realistic visual flythrough", 1996), done exactly for tilted columns by the column-plane
// march below; the per-ray march (RayMarch.h) takes the rows the plane march cannot.
#include "ColumnCaster.h"
#include "RayMarch.h"
#include "SpanFill.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>

namespace fieldcast::core {

using namespace ray_march;  // the per-ray march and its grid helpers

std::uint16_t terrainCeilingQ(const TerrainView& view) noexcept {
  const TerrainGeometry& g = view.geometry();
  const int top = g.levels - 1;
  std::uint16_t ceiling = 0;
  for (int j = 0; j < g.levelHeightVox(top); ++j) {
    for (int i = 0; i < g.levelWidthVox(top); ++i) ceiling = std::max(ceiling, view.maxHeightQ(top, i, j));
  }
  return ceiling;
}

CasterFrame::CasterFrame(const TerrainView& v, const ViewGeometry& geometry, const RenderSettings& settings,
                         std::uint16_t ceiling, Image* img, float* range) noexcept
    : view(&v),
      geo(&geometry),
      shading(settings),
      levels(v.geometry().levels),
      tileShift(v.geometry().tileShift),
      tileMask(v.geometry().tileSizeVox() - 1),
      supersample(std::clamp(settings.verticalSupersample, 1, 4)),
      blend(settings.blendLevels),
      image(img),
      rangeM(range) {
  const TerrainGeometry& g = v.geometry();
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
}

namespace {

// ---------------------------------------------------------------------------------------------
// The column-plane march. All rays of an image column lie in one plane Π through the camera (for
// a pitched camera Π is tilted, not vertical). On each grid line M = M_i of the column's major
// axis, Π cuts a line L_i; where L_i crosses the terrain profile of that grid line (linear between
// voxel centres along the minor axis) is the one terrain point of this grid line that the column
// sees, and projecting it gives the image row v_i where it appears. Walking the grid lines away
// from the camera, the rows between the highest crossing so far and v_i see the terrain between
// grid lines i−1 and i: they are filled by interpolating the two crossings (perspective-correct).
// This is the vertical coherence of the seed paper done exactly for tilted columns: every ray of
// the column is tested at every grid line, yet the work is one crossing per grid line plus one
// fill per pixel, with no per-ray set-up.
// ---------------------------------------------------------------------------------------------

// Grid space: x, y in level-0 voxel units, z in height quanta.
struct ColumnPlane {
  bool xMajor = true;
  int sx = 1;                               // march direction along the major axis (rows go up)
  double nMaj = 0, nMin = 1, nZ = 0;        // plane normal in grid space, oriented so nMin > 0
  double cMaj = 0, cMin = 0, cZ = 0;        // camera in grid space
  double upMaj = 0, upMin = 0, upZ = 0;     // camera up axis, grid deltas → metres
  double fwdMaj = 0, fwdMin = 0, fwdZ = 0;  // camera forward axis, grid deltas → metres
  double aMaj = 0, aMin = 0, aZ = 0;        // the column ray at yc = 0, grid space: ray(yc) = a + yc·b
  double bMaj = 0, bMin = 0, bZ = 0;        // the camera up axis, grid space
  double vHorizon = 0;                      // rows above this (smaller v) look upwards
  double xc = 0;                            // camera-space x of the column (ray = (xc, yc, 1))
  int majSize = 0, minSize = 0;             // level-0 grid size along major / minor
};

// The terrain point of one grid line that the column sees. It is kept in camera space (yc, zc):
// most crossings at low pitch raise the column by less than a row, and telling that (and whether
// a crossing is hidden) takes a multiply, not a division. Only a crossing that bounds a fill is
// projected to its image row; only one that colours a pixel gets a colour.
struct Crossing {
  double yc = 0;        // camera up coordinate (metres)
  double depth = 0;     // camera forward coordinate zc (metres)
  double phi = 0;       // fraction along the segment
  double lodDepth = 0;  // depth the level of detail is chosen for (depth × lodStretch)
  int level = 0;
  int i = 0;  // level-L major index of the grid line
  int j = 0;  // minor segment j .. j+1 (level-L indices)
  bool haveColour = false;
  Rgb colour;
};

// One window per level on the tile last read there: most height and colour reads of the column
// march are two compares and a load. The columns of a staging block share one.
struct TileWindows {
  std::array<const TerrainTile*, 24> tile{};
  std::array<int, 24> x0{};  // level-L voxel of the tile's corner
  std::array<int, 24> y0{};
  TileWindows() {
    x0.fill(std::numeric_limits<int>::min() / 4);
    y0.fill(std::numeric_limits<int>::min() / 4);
  }
};

// Tile of voxel (x, y) at `level` into the window; false when it is outside the grid or missing.
inline bool windowFor(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x, int y) noexcept {
  const auto l = static_cast<std::size_t>(level);
  const unsigned size = 1u << f.tileShift;
  if (static_cast<unsigned>(x - w.x0[l]) < size && static_cast<unsigned>(y - w.y0[l]) < size) return true;
  if (x < 0 || y < 0 || x >= f.levelWidth[l] || y >= f.levelHeight[l]) return false;
  const TerrainTile* tile = tileAt(f, t, level, x >> f.tileShift, y >> f.tileShift);
  if (tile == nullptr) return false;
  w.tile[l] = tile;
  w.x0[l] = (x >> f.tileShift) << f.tileShift;
  w.y0[l] = (y >> f.tileShift) << f.tileShift;
  return true;
}

inline std::uint16_t windowHeight(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x,
                                  int y) noexcept {
  if (!windowFor(f, t, w, level, x, y)) return heightAt(f, t, level, x, y);  // clamped / coarser fallback
  const auto l = static_cast<std::size_t>(level);
  return w.tile[l]->heightQ[((y - w.y0[l]) << f.tileShift) + (x - w.x0[l])];
}

inline std::uint32_t windowColour(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x,
                                  int y) noexcept {
  if (!windowFor(f, t, w, level, x, y)) return colourAt(f, t, level, x, y);
  const auto l = static_cast<std::size_t>(level);
  return w.tile[l]->colourRgba[((y - w.y0[l]) << f.tileShift) + (x - w.x0[l])];
}

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

// Blends the next level's colour (bilinear) into crossing x's, by `blend`. Out of line: half the
// crossings that are coloured need it, and it reads four texels.
[[gnu::noinline]] void blendNextLevel(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c,
                                      Crossing& x, double blend) noexcept {
  const int l = x.level;
  const double p = pow2(l);
  const double mMaj = (x.i + 0.5) * p - 0.5;
  const double mMin = (x.j + 0.5 + x.phi) * p - 0.5;
  const double ux = levelIndex(c.xMajor ? mMaj : mMin, l + 1);
  const double uy = levelIndex(c.xMajor ? mMin : mMaj, l + 1);
  const int x0 = floorToInt(ux);
  const int y0 = floorToInt(uy);
  const auto fx = static_cast<float>(ux - x0);
  const auto fy = static_cast<float>(uy - y0);
  const int up = l + 1;
  std::uint32_t q00, q10, q01, q11;
  const int mask = f.tileMask;
  if ((x0 & mask) != mask && (y0 & mask) != mask && windowFor(f, t, w, up, x0, y0)) {
    // The 2×2 block lies in one tile: four loads.
    const auto lv = static_cast<std::size_t>(up);
    const std::uint32_t* p00 = w.tile[lv]->colourRgba + (((y0 - w.y0[lv]) << f.tileShift) + (x0 - w.x0[lv]));
    const std::ptrdiff_t row = std::ptrdiff_t{1} << f.tileShift;
    q00 = p00[0];
    q10 = p00[1];
    q01 = p00[row];
    q11 = p00[row + 1];
  } else {
    q00 = windowColour(f, t, w, up, x0, y0);
    q10 = windowColour(f, t, w, up, x0 + 1, y0);
    q01 = windowColour(f, t, w, up, x0, y0 + 1);
    q11 = windowColour(f, t, w, up, x0 + 1, y0 + 1);
  }
  const Rgb lo = mix(unpackRgb(q00), unpackRgb(q10), fx);
  const Rgb hi = mix(unpackRgb(q01), unpackRgb(q11), fx);
  x.colour = mix(x.colour, mix(lo, hi, fy), static_cast<float>(blend));
}

// Colour of a crossing: linear along the grid line at its level, blended with the next level.
// Inline: it is asked for twice per fill, and as a call its set-up cost as much as its work.
__attribute__((always_inline)) inline const Rgb& crossingColour(const CasterFrame& f, CasterThread& t, TileWindows& w,
                                                                const ColumnPlane& c, Crossing& x) noexcept {
  if (x.haveColour) return x.colour;
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
  x.colour = mix(unpackRgb(c0), unpackRgb(c1), static_cast<float>(x.phi));
  x.haveColour = true;
  if (!f.blend || l + 1 >= f.levels) return x.colour;
  const double blend = std::clamp(4.0 * x.lodDepth * f.invLodDepth0M * pow2(-l) - 3.0, 0.0, 1.0);  // levelBlend
  if (blend > 0.0) blendNextLevel(f, t, w, c, x, blend);
  return x.colour;
}

// Collects the sub-rows of a column (bottom to top) into pixels of a column-major staging block.
struct ColumnSink {
  const CasterFrame& f;
  int s;
  float scale;
  Rgb sum;
  float range = std::numeric_limits<float>::infinity();
  std::uint8_t* pixels = nullptr;  // this column's pixel in row 0 (rows are consecutive)
  std::size_t bytesPerPixel = 0;
  float* ranges = nullptr;  // this column's range in row 0 (rows are consecutive)

  ColumnSink(const CasterFrame& frame, int subRows, std::uint8_t* columnPixels, float* columnRanges) noexcept
      : f(frame), s(subRows), scale(1.0f / static_cast<float>(subRows)) {
    if (f.image != nullptr) {
      bytesPerPixel = static_cast<std::size_t>(f.shading.bytesPerPixel());
      pixels = columnPixels;
    }
    if (f.rangeM != nullptr) ranges = columnRanges;
  }

  void put(int v, const Rgb& c, float rangeM, float k) const noexcept {
    if (pixels != nullptr) f.shading.storePixel(pixels + static_cast<std::size_t>(v) * bytesPerPixel, c, k);
    if (ranges != nullptr) ranges[v] = rangeM;
  }

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

inline float rayLength(double xc, double yc) noexcept { return static_cast<float>(std::sqrt(1.0 + xc * xc + yc * yc)); }

// Sky in sub-rows q = qFrom ... 0 of the column at camera-space x `xc`: the elevation sine of a ray
// is its world z over its length, both linear / quadratic in the camera-space yc of the row.
void castSkyRows(const CasterFrame& f, CasterThread& t, ColumnSink& sink, double xc, int qFrom) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const CameraAxes& ax = f.geo->axes();
  const double invS = 1.0 / sink.s;
  const double az = xc * ax.right.z + ax.forward.z;
  for (int q = qFrom; q >= 0; --q) {
    const double yc = (k.cyPx - (q + 0.5) * invS) / k.fyPx;
    const float len = rayLength(xc, yc);
    sink.emit(q, f.shading.sky(static_cast<float>(az + yc * ax.up.z) / len), std::numeric_limits<float>::infinity());
  }
  t.rays += static_cast<std::uint64_t>(std::max(qFrom + 1, 0));
}

// Where the column plane march stopped: the level-0 x, y of its last crossing, on a grid line of its
// major axis. The rays of the rows it left pass above all the terrain of the grid lines before.
struct PlaneStop {
  bool valid = false;
  bool xMajor = false;  // the plane's major axis
  glm::dvec2 point{0.0};
  bool overTerrain = false;  // the rows left look over all the terrain: they see the sky
};

// Per-ray casting of sub-rows q = qFrom, qFrom−1, ... (the rows the plane march cannot take: below
// the first hit, and beyond the terrain's edge). Stops after the first hit when `untilHit`.
// Returns the sub-row below which it stopped (−1 when the column is done) and the hit. The first
// ray starts at `resume` when given and it marches along the same major axis (its distance is then
// measured along the grid lines the plane march took; on the other axis the crossing's minor
// offset could put the start past terrain the ray has not been tested against).
int castRowsPerRay(const CasterFrame& f, CasterThread& t, ColumnSink& sink, double uc, int qFrom, bool untilHit,
                   bool& havePrev, glm::dvec2& prevHit, MarchHit& hitOut, RayLine& lineOut,
                   const PlaneStop* resume = nullptr) noexcept {
  const Intrinsics& k = f.geo->intrinsics();
  const double xc = (uc - k.cxPx) / k.fxPx;
  for (int q = qFrom; q >= 0; --q) {
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
        const float rangeM = static_cast<float>(depth) * length;
        sink.emit(q, f.shading.terrain(hitColour(f, t, r, h, depth), rangeM), rangeM);
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
        castSkyRows(f, t, sink, xc, q);
        return -1;
      }
    } else {
      havePrev = false;  // nowhere near the terrain: the next ray starts afresh
    }
    sink.emit(q, f.shading.sky(static_cast<float>(d.z) / length), std::numeric_limits<float>::infinity());
    ++t.rays;
  }
  return -1;
}

// Fills the sub-rows of a supersampled column (several per pixel) between two crossings, as
// fillSpanReference does for one per pixel; the sink averages them into pixels. Its constants are
// copied to locals: the sink's stores would otherwise make them be read again after each one.
__attribute__((always_inline)) inline void fillSpanSubRows(const CrossingSpan span, const ColumnFill& column,
                                                           ColumnSink& sink, double vStop, int& qInOut,
                                                           double& vqInOut) noexcept {
  const ColumnFill local = column;
  int q = qInOut;
  double vq = vqInOut;
  while (vq > vStop) {
    const SpanPixel p = spanPixel(span, local, local.shading, q);
    sink.emit(q, p.colour, p.rangeM);
    if (--q < 0) break;
    vq -= local.invSd;
  }
  qInOut = q;
  vqInOut = vq;
}

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

// What the plane march of a column carries from one grid line to the next, so that it can pause
// at a depth and resume there. castColumns marches the columns of a staging block in step, depth
// band by depth band: all but the first then read heights and texels already in L1.
// (What the loop recomputes from these, such as the level's steps, the next row's slope and the
// grazing-angle stretch, is not kept.)
struct PlaneMarchState {
  bool started = false;  // the march has paused once: the next call resumes from here
  bool paused = false;   // the last call paused (rather than ended)
  int level = 0, i = 0, q = 0, jGuess = 0, prev = 0;
  double base = 0, yLine = 0, zLine = 0, jPos = 0, vq = 0;
  bool lastFilledNothing = false, rayWaitsForSwitch = false;
  Crossing crossings[2]{};
};

// The plane march from the grid line at or before `start` (level-0 x, y of the hit of the ray of
// sub-row q+1) at `level`, filling sub-rows q, q−1, ... Returns the first sub-row it could not
// fill (−1 when the column is done): the march left the terrain, or the rows left look over it.
// `stopped` records its last crossing, where the per-ray march takes the rows left on. Once its
// last crossing lies deeper than `pauseDepth` it pauses instead (state.paused); called again with
// the same state, it goes on from there (q, start and level are then the state's).
template <bool kXMajor>
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
  // The tile of the current level the heights come from, kept in registers: a read is two
  // unsigned compares and a load; anything else goes through the window cache.
  const std::uint16_t* tileHeights = nullptr;
  int wx0 = std::numeric_limits<int>::min() / 4;
  int wy0 = std::numeric_limits<int>::min() / 4;
  const unsigned tileSize = 1u << f.tileShift;
  const auto height = [&](int lv, int i, int j) __attribute__((always_inline))->double {
    const int x = kXMajor ? i : j;
    const int y = kXMajor ? j : i;
    if (static_cast<unsigned>(x - wx0) < tileSize && static_cast<unsigned>(y - wy0) < tileSize) {
      return tileHeights[((y - wy0) << f.tileShift) + (x - wx0)];
    }
    if (windowFor(f, t, window, lv, x, y)) {
      const auto l = static_cast<std::size_t>(lv);
      tileHeights = window.tile[l]->heightQ;
      wx0 = window.x0[l];
      wy0 = window.y0[l];
      return tileHeights[((y - wy0) << f.tileShift) + (x - wx0)];
    }
    return heightAt(f, t, lv, x, y);  // outside the grid (clamped) or tile missing (coarser level)
  };

  // The crossing on grid line i at minor position j + φ (level units) solves g = gA·(j + φ) + nZ·h +
  // base = 0; its camera coordinates are yc = yLine + (j + φ)·yMinor + h·upZ and zc likewise. base,
  // yLine and zLine carry the grid line's major position and grow by a constant step per line, so
  // the hot loop keeps few values live (more than the 16 vector registers made it spill).
  const double nZ = c.nZ, upZ = c.upZ, fwdZ = c.fwdZ;
  double p = 0, gA = 0, baseStep = 0, minOffset = 0, yMinor = 0, zMinor = 0, yStep = 0, zStep = 0;
  double switchDepth = 0;
  int majLast = 0, minLast = 0;
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
    // The register window belongs to the old level.
    tileHeights = nullptr;
    wx0 = std::numeric_limits<int>::min() / 4;
    wy0 = std::numeric_limits<int>::min() / 4;
    // Last grid line inside both the level's grid and the hull of the level-0 voxel centres.
    const int hullLast = sx > 0 ? floorToInt(levelIndex(c.majSize - 1, lv)) : ceilToInt(levelIndex(0.0, lv));
    majLast = sx > 0 ? std::min(hullLast, majSizes[static_cast<std::size_t>(lv)] - 1) : std::max(hullLast, 0);
    minLast = minSizes[static_cast<std::size_t>(lv)] - 2;
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
    while (g0 > 0.0) {
      if (j == 0) return false;
      --j;
      h1 = h0;
      g1 = g0;
      h0 = height(level, i, j);
      g0 -= gA + nZ * (h1 - h0);
      ++samples;
    }
    while (g1 <= 0.0) {
      if (j == minLast) return false;
      ++j;
      h0 = h1;
      g0 = g1;
      h1 = height(level, i, j + 1);
      g1 = g0 + gA + nZ * (h1 - h0);
      ++samples;
    }
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
                        invS};
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
      if (static_cast<unsigned>(x - wx0) < tileSize - (kXMajor ? 0 : 1) &&
          static_cast<unsigned>(y - wy0) < tileSize - (kXMajor ? 1 : 0)) {
        // Both voxels in the register window: one check for the pair.
        const std::uint16_t* pair = tileHeights + (((y - wy0) << f.tileShift) + (x - wx0));
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
      // (Only a crossing that fills rows is projected to its row and coloured.)
      const double prevInvDepth = 1.0 / prev.depth;
      const double curInvDepth = 1.0 / cur.depth;
      const double prevV = k.cyPx - k.fyPx * prev.yc * prevInvDepth;
      const double curV = k.cyPx - k.fyPx * cur.yc * curInvDepth;
      // The sub-rows from the next one up to this crossing's row see the terrain between the two
      // grid lines.
      const CrossingSpan span{static_cast<float>(prevV),
                              static_cast<float>(1.0 / (curV - prevV)),
                              static_cast<float>(prevInvDepth),
                              static_cast<float>(curInvDepth),
                              crossingColour(f, t, window, c, prev),
                              crossingColour(f, t, window, c, cur)};
      const int qFirst = q;
      if (sink.s != 1) {
        fillSpanSubRows(span, fill, sink, curV, q, vq);
      } else if (fill.shading.grey) {
        fillSpan<true>(span, fill, ColumnPixels{sink.pixels, sink.ranges, sink.bytesPerPixel}, curV, q, vq);
      } else {
        fillSpan<false>(span, fill, ColumnPixels{sink.pixels, sink.ranges, sink.bytesPerPixel}, curV, q, vq);
      }
      rowSlope = (k.cyPx - vq) * invFy;
      if (grazingLod) {
        stretch = stretchOfRow(q);
        switchZc = switchDepth / stretch;
      }
      t.rays += static_cast<std::uint64_t>(qFirst - q);
      if (q < 0) {
        recordStop(cur);
        return -1;
      }
    }
    std::swap(prevP, curP);
  }
}

int marchPlane(const CasterFrame& f, CasterThread& t, ColumnSink& sink, const ColumnPlane& c, int q,
               const glm::dvec2& start, int level, PlaneStop& stopped, PlaneMarchState& state, double pauseDepth,
               TileWindows& window) noexcept {
  return c.xMajor ? marchPlaneAxis<true>(f, t, sink, c, q, start, level, stopped, state, pauseDepth, window)
                  : marchPlaneAxis<false>(f, t, sink, c, q, start, level, stopped, state, pauseDepth, window);
}

inline double finiteOrZero(double x) noexcept { return std::isfinite(x) ? x : 0.0; }

// One column being cast: the rays below its first hit, its plane march (which can pause at a
// depth, see castColumns) and the rows the march leaves.
class ColumnCast {
 public:
  ColumnCast(const CasterFrame& f, int u, std::uint8_t* columnPixels, float* columnRanges) noexcept
      : mSink(f, f.supersample, columnPixels, columnRanges), mUc(u + 0.5) {}

  // The bottom rays, one by one until one hits (the first by descending the max pyramid).
  void castBottomRays(const CasterFrame& f, CasterThread& t) noexcept {
    const Intrinsics& k = f.geo->intrinsics();
    mQ = castRowsPerRay(f, t, mSink, mUc, f.supersample * k.heightPx - 1, true, mHavePrev, mPrevHit, mHit, mLine);
    if (mQ < 0) return;
    mPlane = columnPlane(f, mUc);
    mDepth = finiteOrZero(mHit.m / mLine.aMaj);
  }

  bool done() const noexcept { return mQ < 0; }
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
    mQ = -1;
    if (q < 0) return;
    // Above all the terrain, the rows left see the sky. Otherwise (the march left the grid, or
    // could not start) they are cast one by one: a row may look over the terrain's edge and a
    // tilted column come back over it, and a row above the horizon may still meet a slope that
    // rises above the camera. The per-ray march ends the column with sky at the first climbing ray
    // that misses.
    if (mStopped.overTerrain) {
      castSkyRows(f, t, mSink, mPlane.xc, q);
      return;
    }
    castRowsPerRay(f, t, mSink, mUc, q, false, mHavePrev, mPrevHit, mHit, mLine, &mStopped);
  }

 private:
  ColumnSink mSink;
  double mUc;
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
// `dst` (`stride` bytes apart). Bytes is a constant so each copy is one move.
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
      ColumnCast& column = block[static_cast<std::size_t>(u - b0)].emplace(f, u, t.columnPixels.data() + c * bpp,
                                                                           t.columnRanges.data() + c);
      column.castBottomRays(f, t);
      if (!column.done()) nearest = std::min(nearest, column.depth());
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
    for (int v = k.heightPx - 1; v >= 0; --v) {
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
            const auto rangeM = static_cast<float>(depth * length);
            const Rgb c = f.shading.terrain(hitColour(f, t, r, h, depth), rangeM);
            sum += c;
            if (sub == s / 2) rangePx = rangeM;
            continue;
          }
          // Missed. An ascending ray passes over everything, and so does every ray above it. A
          // descending one left the terrain's side; the ray above starts where this one left (a
          // pitched column fans out in azimuth, so it may come back over the terrain: retrace).
          if (d.z >= 0.0) sky = true;
        } else {
          havePrev = false;  // nowhere near the terrain: the next ray starts afresh
        }
        const Rgb c = f.shading.sky(static_cast<float>(d.z / length));
        sum += c;
      }
      if (f.image != nullptr) f.shading.store(f.image->row(v), u, sum, scale);
      if (f.rangeM != nullptr)
        f.rangeM[static_cast<std::size_t>(v) * static_cast<std::size_t>(k.widthPx) + u] = rangePx;
    }
  }
}

CastResult castRay(const CasterFrame& f, double u, double v, CasterThread& t) noexcept {
  const glm::dvec3 d = f.geo->ray(u, v);
  RayLine r;
  CastResult out;
  if (!setupLine(f, d, r)) return out;
  const MarchHit h = march(f, t, r, firstHitStart(f, r));
  if (!h.hit) return out;
  out.hit = true;
  out.level = h.at.level;
  out.depthM = h.m / r.aMaj;
  out.pointM = worldPoint(f, r, h.m);
  const int j = static_cast<int>(h.at.y >> 32);
  out.colour = r.xMajor ? colourAt(f, t, h.at.level, h.at.i, j) : colourAt(f, t, h.at.level, j, h.at.i);
  return out;
}

}  // namespace fieldcast::core
