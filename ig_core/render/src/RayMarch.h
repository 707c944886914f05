#pragma once
// The per-ray march: one ray on its own line through the horizontal grid (a pitched camera's
// column is not a vertical plane, so the rays of a column have slightly different azimuths;
// marching each on its own line keeps them exact). The march samples the terrain where the ray
// crosses the grid lines of its major axis: there the height field is the linear interpolation of
// two voxels along the minor axis, so each step is two 16-bit loads, a multiply and a compare, in
// fixed point. The column caster uses it for the rows its plane march cannot take, castRay for
// single rays; castColumnsPerRay casts whole columns with it. Its grid helpers and tile access
// (floorToInt to colourAt) serve the plane march too.
//
// Units: "m" is the distance along the ray's major axis in level-0 voxel units from the camera;
// at level L the grid lines lie at level-0 coordinate (i + ½)·2^L − ½, so one step is 2^L units.
// Minor positions are level-L voxel indices in 32.32 fixed point; heights are quanta in 48.16.
// Private to ig_core.

#include "ColumnCaster.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <bit>
#include <cstdint>

namespace fieldcast::core::ray_march {

/// One ray's line through the grid, in level-0 units, fixed for the whole march.
struct RayLine {
  bool xMajor = true;
  int sx = 1;             ///< direction of the major axis: +1 or −1
  double cMaj = 0;        ///< camera on the major axis
  double cMin = 0;        ///< camera on the minor axis
  double slope = 0;       ///< minor units per unit of m
  double zPer = 0;        ///< height quanta per unit of m
  double aMaj = 1;        ///< units of m per metre of depth
  double mUnit = 1;       ///< level L is used while m ≤ mUnit·2^L
  double lodStretch = 1;  ///< ViewGeometry::lodStretch of the ray
  double invMUnit = 1;
  double mEnter = 0;  ///< first m inside the terrain's box (hull of voxel centres, below the ceiling)
  double mExit = 0;   ///< last m inside that box
};

/// floor/ceil without a libm call (the values are grid indices, well inside int range).
inline int floorToInt(double x) noexcept {
  const int i = static_cast<int>(x);
  return i - (x < i);
}
inline int ceilToInt(double x) noexcept {
  const int i = static_cast<int>(x);
  return i + (x > i);
}
inline std::int64_t floorToInt64(double x) noexcept {
  const auto i = static_cast<std::int64_t>(x);
  return i - (x < static_cast<double>(i));
}
/// 2^level as a double, exactly, without ldexp.
inline double pow2(int level) noexcept { return std::bit_cast<double>(static_cast<std::uint64_t>(1023 + level) << 52); }

/// Continuous level-L index of level-0 coordinate x.
inline double levelIndex(double x, int level) noexcept { return (x + 0.5) * pow2(-level) - 0.5; }

/// Sets up the line of ray direction `d` (forward component 1); false when the ray misses the
/// terrain's box entirely.
bool setupLine(const CasterFrame& f, const glm::dvec3& d, RayLine& r) noexcept;

/// Where along the line (its parameter m) it crosses grid line `i` of `level`. RT-safe.
double lineM(const RayLine& r, int i, int level) noexcept;

/// Tile of (level, tx, ty) through the worker's one-entry-per-level cache; null when missing or
/// outside the grid.
/// (Out of line: inlined into the plane march's tile windows it cost 2–4% more instructions.)
[[gnu::noinline]] const TerrainTile* tileAt(const CasterFrame& f, CasterThread& t, int level, int tx, int ty) noexcept;

/// Height and colour of voxel (x, y) of `level`, clamped to the grid, falling back to coarser
/// levels when the tile is missing.
std::uint16_t heightAt(const CasterFrame& f, CasterThread& t, int level, int x, int y) noexcept;
std::uint32_t colourAt(const CasterFrame& f, CasterThread& t, int level, int x, int y) noexcept;
/// The stick of voxel (x, y) of `level` (id 0: none, always so on a terrain without sticks),
/// clamped to the grid, from the coarser level that stands in when the tile is missing.
StickVoxel stickAt(const CasterFrame& f, CasterThread& t, int level, int x, int y) noexcept;

/// The factor the frame's sun scales the terrain colour at fraction `phi` of the grid segment from
/// voxel (x, y) of `level` to its east (alongX) or north neighbour by: each voxel's
/// TerrainLight::terrain of its slope (minmod of the differences to its neighbours on each axis),
/// linear between them as the colours are. Call only for a relit frame. Out of line: a frame lit
/// by the colours' own sun never calls it.
[[gnu::noinline]] float segmentLight(const CasterFrame& f, CasterThread& t, int level, int x, int y, bool alongX,
                                     float phi) noexcept;

/// The march state at one grid line of one level.
struct Cursor {
  int level = 0;
  int i = 0;           ///< level-L major index
  std::int64_t y = 0;  ///< level-L minor index, 32.32
  std::int64_t z = 0;  ///< ray height, quanta 48.16
};

/// Result of a march: the grid line where the ray went below the surface, and the distance m of
/// the crossing (linear between the last sample above and the first below).
struct MarchHit {
  bool hit = false;
  Cursor at;
  double m = 0.0;
};

/// Marches ray `r` from distance mStart (where the ray below hit, or the first-hit estimate) to its
/// first crossing of the surface; a start below the surface is retraced backwards. A miss returns
/// hit = false with m = the distance where the ray left the terrain.
MarchHit march(const CasterFrame& f, CasterThread& t, const RayLine& r, double mStart) noexcept;

/// First hit of a ray without a predecessor: descend the conservative max pyramid, skipping every
/// cell the ray crosses above its maximum, until the cell is at the ray's level of detail.
double firstHitStart(const CasterFrame& f, const RayLine& r) noexcept;

/// Marches one ray of a column with vertical coherence: from where the ray below it hit
/// (projected onto this ray's own line), or from the first hit found in the max pyramid when
/// there is no ray below. Records where this ray stopped for the ray above it.
MarchHit marchCoherent(const CasterFrame& f, CasterThread& t, const RayLine& r, bool& havePrev,
                       glm::dvec2& prevHit) noexcept;

/// Colour at a hit: linear along the grid line at the hit's level, blended with the next level
/// (bilinear there) by distance; on a stick's side or top, the stick's colour (StickShading.h),
/// and its texel in `stickTexelOut` when given (it may be see-through).
Rgb hitColour(const CasterFrame& f, CasterThread& t, const RayLine& r, const MarchHit& h, double depthM,
              std::uint32_t* stickTexelOut = nullptr) noexcept;

/// World position (metres) of the point at distance m along the ray.
glm::dvec3 worldPoint(const CasterFrame& f, const RayLine& r, double m) noexcept;

}  // namespace fieldcast::core::ray_march
