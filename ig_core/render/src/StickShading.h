#pragma once
// The colour of sticks (ig_core/README.md, "Sticks"), shared by the fast caster and the reference
// renderer. A voxel with a stick has its stick's top as its height, so the surface between it and
// a lower neighbour is the stick's side; a point there, or on its top, takes the stick's colour at
// its depth below the top — nearest texel, no level blend (the table's mips filter it instead).
// Between two voxels that both carry sticks the taller one colours it.

#include "Shading.h"

#include <ig_core/Sticks.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>

namespace fieldcast::core {

/// A voxel's stick as the renderers see it: its id (0: none), its top (height quanta), and the
/// level whose colours it takes (the voxel's own, or the coarser one that stood in for it).
struct StickVoxel {
  std::uint32_t id = 0;
  std::uint16_t topQ = 0;
  int level = 0;
};

/// The stick that colours a point between voxels a and b: the taller of those that carry one.
inline StickVoxel colouringStick(const StickVoxel& a, const StickVoxel& b) noexcept {
  if (a.id == 0) return b;
  if (b.id == 0 || a.topQ >= b.topQ) return a;
  return b;
}

/// Where height zQ (quanta) lies on stick s: texels of its level below its top. `unitsPerQ` is
/// the height step over the table's unit (level-0 stick voxels per quantum).
inline float stickTexelCoordinate(const StickVoxel& s, double zQ, double unitsPerQ) noexcept {
  // × 2^−level: exact, as ldexp would be, without its call
  return static_cast<float>((s.topQ - zQ) * unitsPerQ * (1.0 / static_cast<double>(1u << s.level)));
}

/// Whether texel `rgba` is see-through: alpha below 255, only ever at level 0 of a complex stick.
inline bool seeThroughTexel(std::uint32_t rgba) noexcept { return (rgba >> 24) != 0xFFu; }

/// The texel at `coordinate` (floor, clamped to the stick: above its top the first, below its
/// foot the last; NaN the first).
inline std::uint32_t stickTexel(std::span<const std::uint32_t> texels, float coordinate) noexcept {
  const float last = static_cast<float>(texels.size() - 1);
  const float k = coordinate > 0.0f ? std::floor(coordinate) : 0.0f;
  return texels[static_cast<std::size_t>(k < last ? k : last)];
}

/// The layers a ray seen through complex sticks passes (SeeThrough.h), composited front to back:
/// each colour already hazed at its own range, with its opacity; the range kept is where the layers
/// become at least half opaque (infinite while they are not).
struct SeeThroughLayers {
  Float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
  float opacity = 0.0f;
  float rangeM = std::numeric_limits<float>::infinity();

  void add(const Rgb& hazed, float alpha, float range) noexcept {
    const float w = (1.0f - opacity) * alpha;
    sum += hazed.v * w;
    if (opacity < 0.5f && opacity + w >= 0.5f) rangeM = range;
    opacity += w;
  }
  /// The composite, with `hazed` at `range` as the opaque last layer.
  std::pair<Rgb, float> finish(const Rgb& hazed, float range) noexcept {
    add(hazed, 1.0f, range);
    return {Rgb{sum}, rangeM};
  }
};

}  // namespace fieldcast::core
