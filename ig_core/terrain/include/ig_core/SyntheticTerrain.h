#pragma once
// Small procedural terrains built in memory, for tests, benchmarks and tools that must not depend
// on a database: rolling hills with a textured colour, and a flat textured plane (LOD seam test).

#include <ig_core/MemoryTerrain.h>

#include <cstdint>
#include <memory>

namespace fieldcast::core {

/// What a synthetic terrain looks like.
enum class SyntheticKind : std::uint8_t {
  Hills,      ///< fractal value-noise hills (0..~400 m) with an elevation palette and fine texture
  FlatPlane,  ///< height 0 everywhere; colour = smooth sinusoids plus a one-voxel checker
};

/// Parameters of a synthetic terrain.
struct SyntheticTerrainSpec {
  SyntheticKind kind = SyntheticKind::Hills;
  int sizeVox = 1024;      ///< voxels per side (square grid)
  double spacingM = 2.0;   ///< level-0 voxel pitch
  int tileShift = 6;       ///< tile side 2^tileShift voxels
  std::uint32_t seed = 1;  ///< noise seed
};

/// Builds a fully resident synthetic terrain; the grid's south-west voxel centre is at (0, 0).
/// Deterministic for a given spec. Not RT-safe (allocates, takes ~0.1 s per million voxels).
std::unique_ptr<MemoryTerrain> makeSyntheticTerrain(const SyntheticTerrainSpec& spec);

}  // namespace fieldcast::core
