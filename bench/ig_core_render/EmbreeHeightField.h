#pragma once
// An independent renderer of the same terrain, for scale: Intel Embree 3 (libembree-dev) ray
// casting level 0 as a height field — Embree's grid geometry, one vertex per voxel centre, one
// grid primitive per 256² voxels — with primary rays in packets of 16 (4 × 4 pixels). Each pixel
// takes the colour of the voxel nearest its hit: no level of detail, no filtering, no shading.

#include "LevelZeroGrid.h"

#include <ig_core/ViewGeometry.h>

#include <cstddef>
#include <cstdint>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace fieldcast::core {

class EmbreeHeightField {
 public:
  /// Builds the scene (the BVH) over `grid`, which must outlive this. Throws std::runtime_error
  /// with Embree's message when Embree fails.
  explicit EmbreeHeightField(const LevelZeroGrid& grid);
  ~EmbreeHeightField();
  EmbreeHeightField(const EmbreeHeightField&) = delete;
  EmbreeHeightField& operator=(const EmbreeHeightField&) = delete;

  /// Renders the frame of `view` (RGB, its intrinsics' size) on `threads` threads into `rgb`,
  /// and each pixel's range along its ray into `rangeM` when given (metres, +inf: sky).
  /// Returns how many pixels hit the terrain.
  std::size_t render(const ViewGeometry& view, int threads, std::vector<std::uint8_t>& rgb,
                     std::vector<float>* rangeM = nullptr) const;

 private:
  const LevelZeroGrid& mGrid;
  std::vector<float> mVertices;  // x, y, z per voxel centre, metres from the terrain's origin
  RTCDeviceTy* mDevice = nullptr;
  RTCSceneTy* mScene = nullptr;
};

}  // namespace fieldcast::core
