#pragma once
// An independent renderer of the same terrain, for scale: a VoxelSpace-style column renderer (the
// 1992 Comanche engine's method). Each image column walks its ray's ground track front to back in
// steps that grow with distance (a step covers about one pixel across, never less than a voxel),
// projects each sample's height with the pitch as a vertical shear instead of a rotation, and
// fills the rows above the highest so far with the nearest voxel's flat colour. No sub-voxel hits,
// no filtering: fast, and an inexact picture — comparable only for views near the horizon.

#include "LevelZeroGrid.h"

#include <ig_core/ViewGeometry.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fieldcast::core {

/// Renders the frame of `view` (RGB, its intrinsics' size) from `grid` on `threads` threads into
/// `rgb`. Returns how many pixels show terrain.
std::size_t renderVoxelSpace(const LevelZeroGrid& grid, const ViewGeometry& view, int threads,
                             std::vector<std::uint8_t>& rgb);

}  // namespace fieldcast::core
