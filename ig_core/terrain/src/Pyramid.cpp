// The pyramid, level by level, each level's rows shared among threads: a coarse row reads only
// the two rows below it, and the max mip's dilation reads only the raw maxima, so rows are
// independent and the result does not depend on how they were shared.
// Sticks keep their height up the pyramid: a coarse voxel over a stick takes the tallest stick's
// top and id (a lone tree stays a tree far away instead of a bump a quarter its height).
#include <ig_core/Pyramid.h>

#include "Parallel.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fieldcast::core {
namespace {

// Rows per chunk of work: about 64 Ki voxels, enough to pay for handing it out
std::size_t rowsPerChunk(int widthVox) noexcept {
  return std::max<std::size_t>(1, (std::size_t{1} << 16) / static_cast<std::size_t>(std::max(widthVox, 1)));
}

std::uint32_t averageRgba(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) noexcept {
  std::uint32_t out = 0;
  for (int shift = 0; shift < 32; shift += 8) {
    const std::uint32_t sum =
        ((a >> shift) & 0xFFu) + ((b >> shift) & 0xFFu) + ((c >> shift) & 0xFFu) + ((d >> shift) & 0xFFu);
    out |= ((sum + 2) / 4) << shift;
  }
  return out;
}

// Max of each voxel's 3×3 neighbourhood (edges clamped): the raw maxima become a bound that
// covers the neighbours a bilinear sample inside the voxel can read. Row by row: the column
// maxima of rows j-1..j+1, then the maxima along the row.
void dilate3x3(const std::uint16_t* raw, int w, int h, std::uint16_t* result, int threads) {
  const auto row = [&](int j) { return raw + static_cast<std::size_t>(j) * static_cast<std::size_t>(w); };
  detail::parallelFor(static_cast<std::size_t>(h), threads, rowsPerChunk(w), [&](std::size_t begin, std::size_t end) {
    std::vector<std::uint16_t> columns(static_cast<std::size_t>(w));
    for (auto j = static_cast<int>(begin); j < static_cast<int>(end); ++j) {
      const std::uint16_t* above = row(std::max(j - 1, 0));
      const std::uint16_t* here = row(j);
      const std::uint16_t* below = row(std::min(j + 1, h - 1));
      for (int i = 0; i < w; ++i) columns[static_cast<std::size_t>(i)] = std::max({above[i], here[i], below[i]});
      std::uint16_t* out = result + static_cast<std::size_t>(j) * static_cast<std::size_t>(w);
      for (int i = 0; i < w; ++i) {
        out[i] = std::max({columns[static_cast<std::size_t>(std::max(i - 1, 0))], columns[static_cast<std::size_t>(i)],
                           columns[static_cast<std::size_t>(std::min(i + 1, w - 1))]});
      }
    }
  });
}

}  // namespace

Pyramid buildPyramid(const TerrainGeometry& geometry, std::span<const std::uint16_t> heightQ,
                     std::span<const std::uint32_t> colourRgba, std::span<const std::uint32_t> stickId, int threads) {
  const auto count = static_cast<std::size_t>(geometry.widthVox) * static_cast<std::size_t>(geometry.heightVox);
  if (heightQ.size() != count || colourRgba.size() != count || (!stickId.empty() && stickId.size() != count)) {
    throw std::invalid_argument("buildPyramid: expected " + std::to_string(count) + " voxels, got " +
                                std::to_string(heightQ.size()) + " heights, " + std::to_string(colourRgba.size()) +
                                " colours and " + std::to_string(stickId.size()) + " stick ids");
  }
  const bool sticks = !stickId.empty();
  Pyramid pyramid;
  pyramid.mLevels.resize(static_cast<std::size_t>(geometry.levels));
  pyramid.mStorage.resize(static_cast<std::size_t>(geometry.levels));

  // Level 0: the caller's arrays, and the dilated heights as its max mip
  pyramid.mStorage[0].maxHeightQ = std::make_unique_for_overwrite<std::uint16_t[]>(count);
  dilate3x3(heightQ.data(), geometry.widthVox, geometry.heightVox, pyramid.mStorage[0].maxHeightQ.get(), threads);
  pyramid.mLevels[0] = PyramidLevel{geometry.widthVox, geometry.heightVox,
                                    heightQ,           {pyramid.mStorage[0].maxHeightQ.get(), count},
                                    colourRgba,        stickId};

  // The raw maxima of the level below (level 0: its heights), from which the next max mip is dilated
  std::unique_ptr<std::uint16_t[]> rawOwned;
  const std::uint16_t* raw = heightQ.data();
  for (int level = 1; level < geometry.levels; ++level) {
    const PyramidLevel below = pyramid.mLevels[static_cast<std::size_t>(level - 1)];
    Pyramid::Storage& own = pyramid.mStorage[static_cast<std::size_t>(level)];
    const int w = geometry.levelWidthVox(level);
    const int h = geometry.levelHeightVox(level);
    const auto size = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    own.heightQ = std::make_unique_for_overwrite<std::uint16_t[]>(size);
    own.maxHeightQ = std::make_unique_for_overwrite<std::uint16_t[]>(size);
    own.colourRgba = std::make_unique_for_overwrite<std::uint32_t[]>(size);
    if (sticks) own.stickId = std::make_unique_for_overwrite<std::uint32_t[]>(size);
    auto rawUp = std::make_unique_for_overwrite<std::uint16_t[]>(size);

    detail::parallelFor(static_cast<std::size_t>(h), threads, rowsPerChunk(w), [&](std::size_t begin, std::size_t end) {
      for (auto j = static_cast<int>(begin); j < static_cast<int>(end); ++j) {
        const int j0 = 2 * j;
        const int j1 = std::min(2 * j + 1, below.heightVox - 1);
        for (int i = 0; i < w; ++i) {
          const int i0 = 2 * i;
          const int i1 = std::min(2 * i + 1, below.widthVox - 1);
          const auto idx = [&](int a, int b) {
            return static_cast<std::size_t>(b) * static_cast<std::size_t>(below.widthVox) + static_cast<std::size_t>(a);
          };
          const std::size_t o = static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
          const unsigned sum = below.heightQ[idx(i0, j0)] + below.heightQ[idx(i1, j0)] + below.heightQ[idx(i0, j1)] +
                               below.heightQ[idx(i1, j1)];
          own.heightQ[o] = static_cast<std::uint16_t>((sum + 2) / 4);
          own.colourRgba[o] = averageRgba(below.colourRgba[idx(i0, j0)], below.colourRgba[idx(i1, j0)],
                                          below.colourRgba[idx(i0, j1)], below.colourRgba[idx(i1, j1)]);
          rawUp[o] = std::max({raw[idx(i0, j0)], raw[idx(i1, j0)], raw[idx(i0, j1)], raw[idx(i1, j1)]});
          if (sticks) {
            // The tallest stick below, if any: its top and id — unless the filtered height stands
            // above it (a hedge at the foot of a slope), which keeps the terrain's voxel
            std::uint32_t id = 0;
            std::uint16_t top = 0;
            for (const std::size_t child : {idx(i0, j0), idx(i1, j0), idx(i0, j1), idx(i1, j1)}) {
              if (below.stickId[child] != 0 && (id == 0 || below.heightQ[child] > top)) {
                id = below.stickId[child];
                top = below.heightQ[child];
              }
            }
            own.stickId[o] = 0;
            if (id != 0 && top >= own.heightQ[o]) {
              own.stickId[o] = id;
              own.heightQ[o] = top;
            }
          }
        }
      }
    });
    dilate3x3(rawUp.get(), w, h, own.maxHeightQ.get(), threads);
    rawOwned = std::move(rawUp);
    raw = rawOwned.get();
    pyramid.mLevels[static_cast<std::size_t>(level)] = PyramidLevel{
        w,
        h,
        {own.heightQ.get(), size},
        {own.maxHeightQ.get(), size},
        {own.colourRgba.get(), size},
        sticks ? std::span<const std::uint32_t>{own.stickId.get(), size} : std::span<const std::uint32_t>{}};
  }
  return pyramid;
}

void cutTile(const PyramidLevel& level, int tileShift, int tx, int ty, std::span<std::uint16_t> heightQ,
             std::span<std::uint16_t> maxHeightQ, std::span<std::uint32_t> colourRgba,
             std::span<std::uint32_t> stickId) {
  const int size = 1 << tileShift;
  for (int y = 0; y < size; ++y) {
    const int j = std::min((ty << tileShift) + y, level.heightVox - 1);
    for (int x = 0; x < size; ++x) {
      const int i = std::min((tx << tileShift) + x, level.widthVox - 1);
      const std::size_t src = static_cast<std::size_t>(j) * static_cast<std::size_t>(level.widthVox) + i;
      const std::size_t dst = static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + x;
      heightQ[dst] = level.heightQ[src];
      maxHeightQ[dst] = level.maxHeightQ[src];
      colourRgba[dst] = level.colourRgba[src];
      if (!stickId.empty()) stickId[dst] = level.stickId.empty() ? 0u : level.stickId[src];
    }
  }
}

}  // namespace fieldcast::core
