#pragma once
// One grid line of the lane march (LaneMarch.h) for all its lanes at once: each lane's crossing
// from the heights of its guessed segment, whether it fills rows, whether its next row's ray has
// left the terrain, and its next guess. In SIMD lanes at the dispatched level
// (LaneLineLanes.cpp); solveLaneLineReference is the scalar form, the same to the bit. Private to
// ig_core.

#include <cstdint>

namespace fieldcast::core::plane_march {

/// The lanes of a line, eight at most (kLaneColumns).
constexpr int kLineLanes = 8;

/// One grid line's solve for a block's lanes, structure of arrays. A lane's column plane g(minor,
/// h) = gA·minor + nZ·h + base is negative below the terrain side of its trace on the line.
struct LaneLine {
  // In, per lane
  alignas(64) double gA[kLineLanes];
  alignas(64) double nZ[kLineLanes];
  alignas(64) double base[kLineLanes];
  alignas(64) double drift[kLineLanes];        ///< minor change of the plane's trace per line
  alignas(64) double rowSlope[kLineLanes];     ///< yc / zc of the lane's next sub-row's ray
  alignas(64) double rayClimbs[kLineLanes];    ///< 1 where that ray climbs along the march, else 0
  alignas(64) double rayZPerDMaj[kLineLanes];  ///< and its height gain per unit of dMaj
  alignas(64) double h0[kLineLanes];           ///< heights of the guessed segment's ends (quanta)
  alignas(64) double h1[kLineLanes];
  alignas(64) std::int32_t j[kLineLanes];  ///< the guessed segment j .. j + 1
  // In, the line's (the camera's axes, the same for every lane)
  double yLine = 0, zLine = 0, yMinor = 0, zMinor = 0, upZ = 0, fwdZ = 0;
  double rayZAtLine = 0;  ///< the camera's height (quanta) ...
  double dMaj = 0;        ///< ... and the line's major offset from it: a ray is at rayZAtLine + dMaj·rayZPerDMaj
  double ceilingQ = 0;    ///< the terrain's highest height
  // Out, per lane
  alignas(64) double yc[kLineLanes];  ///< the crossing's camera coordinates ...
  alignas(64) double depth[kLineLanes];
  alignas(64) double phi[kLineLanes];          ///< ... its fraction along the segment ...
  alignas(64) double heightQ[kLineLanes];      ///< ... and the terrain's height there
  alignas(64) double jPos[kLineLanes];         ///< the next line's predicted minor position
  alignas(64) std::int32_t jNext[kLineLanes];  ///< and segment (nextSegment)
  /// The guess held (g changes sign on the segment) and the crossing lies in front of the camera;
  /// otherwise the lane's solve walks along the line (or fails) in scalar code.
  alignas(64) std::uint8_t solved[kLineLanes];
  alignas(64) std::uint8_t fills[kLineLanes];        ///< the next sub-row's ray passes below the crossing
  alignas(64) std::uint8_t overTerrain[kLineLanes];  ///< that ray is above all the terrain here, climbing
};

/// Solves every lane of `line` (all kLineLanes: unused lanes give values nobody reads) in SIMD
/// lanes at the dispatched level. RT-safe.
void solveLaneLine(LaneLine& line) noexcept;

/// solveLaneLine lane by lane in plain C++: the judge of its SIMD forms.
inline void solveLaneLineReference(LaneLine& l) noexcept {
  for (int n = 0; n < kLineLanes; ++n) {
    const double g0 = l.gA[n] * l.j[n] + l.nZ[n] * l.h0[n] + l.base[n];
    const double g1 = g0 + l.gA[n] + l.nZ[n] * (l.h1[n] - l.h0[n]);
    const double phi = g0 / (g0 - g1);
    const double minor = l.j[n] + phi;
    const double h = l.h0[n] + phi * (l.h1[n] - l.h0[n]);
    const double zc = l.zLine + minor * l.zMinor + h * l.fwdZ;
    const double yc = l.yLine + minor * l.yMinor + h * l.upZ;
    l.yc[n] = yc;
    l.depth[n] = zc;
    l.phi[n] = phi;
    l.heightQ[n] = h;
    l.solved[n] = g0 <= 0.0 && g1 > 0.0 && zc > 1e-6;
    l.fills[n] = yc > l.rowSlope[n] * zc;
    l.overTerrain[n] = l.rayClimbs[n] > 0.0 && l.rayZAtLine + l.dMaj * l.rayZPerDMaj[n] > l.ceilingQ;
    l.jPos[n] = minor + l.drift[n];
    // nextSegment (PlaneMarch.h)
    const double dg = g0 - g1;
    l.jNext[n] = l.j[n] + static_cast<int>(g0 <= (1.0 - l.drift[n]) * dg) - static_cast<int>(g0 > -l.drift[n] * dg);
  }
}

}  // namespace fieldcast::core::plane_march
