#pragma once
// A terrain height that is never below the surface, for keeping a scripted flight clear of the
// ground: the conservative max mip of one level (DESIGN.md §2, "Pyramid"), smoothed so that the
// bound is continuous. Asked of a pinned level, it never misses a tile and never changes while
// tiles load, so a flight lifted over it does not jump when the fine tiles arrive.

#include <ig_core/TerrainView.h>

namespace fieldcast::app {

/// Height in metres at world (x, y) that bounds from above the bilinear surface of every level
/// 0..`level`: bilinear between the voxel centres of `level`, each taking the largest max-mip value
/// of its 3 × 3 neighbourhood (the four centres' neighbourhoods all hold the voxel whose area
/// contains the point, and that voxel's max mip bounds the surface there). RT-safe.
double terrainCeilingM(const core::TerrainView& view, int level, double xM, double yM) noexcept;

}  // namespace fieldcast::app
