#pragma once
// What a tile prefetch needs to know of the frames it fetches for: the levels of detail they draw.

namespace fieldcast::core {

/// The levels of detail of the frames a prefetch is for (ig_core::RenderSettings, prefetchLod()):
/// level L is drawn where its voxels project to at least `quality` pixels; with the grazing-angle
/// rule on, up to `grazingStretch` times nearer the camera than that along grazing rays.
struct PrefetchLod {
  double quality = 1.0;
  double grazingStretch = 1.0;  ///< RenderSettings::maxLodStretch with the grazing rule on, else 1
};

}  // namespace fieldcast::core
