// The binary pyramid of DESIGN.md §2: each level halves the one below with a 2×2 box filter
// (heights and colours), and a conservative max mip bounds the surface for empty-space skipping.
// Sticks keep their height up the pyramid: a coarse voxel over a stick takes the tallest stick's
// top and id (a lone tree stays a tree far away instead of a bump a quarter its height).
#include <ig_core/MemoryTerrain.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fieldcast::core {
namespace {

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
// covers the neighbours a bilinear sample inside the voxel can read.
std::vector<std::uint16_t> dilate3x3(const std::vector<std::uint16_t>& raw, int w, int h) {
  std::vector<std::uint16_t> rows(raw.size());
  for (int j = 0; j < h; ++j) {
    const std::uint16_t* in = raw.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(w);
    std::uint16_t* out = rows.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(w);
    for (int i = 0; i < w; ++i) {
      out[i] = std::max({in[std::max(i - 1, 0)], in[i], in[std::min(i + 1, w - 1)]});
    }
  }
  std::vector<std::uint16_t> result(raw.size());
  const auto at = [&](int i, int j) { return rows[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + i]; };
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      result[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + i] =
          std::max({at(i, std::max(j - 1, 0)), at(i, j), at(i, std::min(j + 1, h - 1))});
    }
  }
  return result;
}

}  // namespace

std::vector<PyramidLevel> buildPyramid(const TerrainGeometry& geometry, std::span<const std::uint16_t> heightQ,
                                       std::span<const std::uint32_t> colourRgba,
                                       std::span<const std::uint32_t> stickId) {
  const auto count = static_cast<std::size_t>(geometry.widthVox) * static_cast<std::size_t>(geometry.heightVox);
  if (heightQ.size() != count || colourRgba.size() != count || (!stickId.empty() && stickId.size() != count)) {
    throw std::invalid_argument("buildPyramid: expected " + std::to_string(count) + " voxels, got " +
                                std::to_string(heightQ.size()) + " heights, " + std::to_string(colourRgba.size()) +
                                " colours and " + std::to_string(stickId.size()) + " stick ids");
  }
  const bool sticks = !stickId.empty();
  std::vector<PyramidLevel> levels(static_cast<std::size_t>(geometry.levels));
  std::vector<std::uint16_t> raw(heightQ.begin(), heightQ.end());  // raw maxima of the level below
  levels[0] = PyramidLevel{geometry.widthVox,
                           geometry.heightVox,
                           std::vector<std::uint16_t>(heightQ.begin(), heightQ.end()),
                           {},
                           std::vector<std::uint32_t>(colourRgba.begin(), colourRgba.end()),
                           {}};
  levels[0].maxHeightQ = dilate3x3(raw, geometry.widthVox, geometry.heightVox);
  if (sticks) levels[0].stickId.assign(stickId.begin(), stickId.end());

  for (int level = 1; level < geometry.levels; ++level) {
    const PyramidLevel& below = levels[static_cast<std::size_t>(level - 1)];
    PyramidLevel& out = levels[static_cast<std::size_t>(level)];
    out.widthVox = geometry.levelWidthVox(level);
    out.heightVox = geometry.levelHeightVox(level);
    const auto size = static_cast<std::size_t>(out.widthVox) * static_cast<std::size_t>(out.heightVox);
    out.heightQ.resize(size);
    out.colourRgba.resize(size);
    if (sticks) out.stickId.assign(size, 0u);
    std::vector<std::uint16_t> rawUp(size);
    for (int j = 0; j < out.heightVox; ++j) {
      const int j0 = 2 * j;
      const int j1 = std::min(2 * j + 1, below.heightVox - 1);
      for (int i = 0; i < out.widthVox; ++i) {
        const int i0 = 2 * i;
        const int i1 = std::min(2 * i + 1, below.widthVox - 1);
        const auto idx = [&](int a, int b) {
          return static_cast<std::size_t>(b) * static_cast<std::size_t>(below.widthVox) + static_cast<std::size_t>(a);
        };
        const std::size_t o = static_cast<std::size_t>(j) * static_cast<std::size_t>(out.widthVox) + i;
        const unsigned sum = below.heightQ[idx(i0, j0)] + below.heightQ[idx(i1, j0)] + below.heightQ[idx(i0, j1)] +
                             below.heightQ[idx(i1, j1)];
        out.heightQ[o] = static_cast<std::uint16_t>((sum + 2) / 4);
        out.colourRgba[o] = averageRgba(below.colourRgba[idx(i0, j0)], below.colourRgba[idx(i1, j0)],
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
          if (id != 0 && top >= out.heightQ[o]) {
            out.stickId[o] = id;
            out.heightQ[o] = top;
          }
        }
      }
    }
    out.maxHeightQ = dilate3x3(rawUp, out.widthVox, out.heightVox);
    raw = std::move(rawUp);
  }
  return levels;
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

MemoryTerrain::MemoryTerrain(TerrainGeometry geometry, std::span<const std::uint16_t> heightQ,
                             std::span<const std::uint32_t> colourRgba, std::span<const std::uint32_t> stickId,
                             std::shared_ptr<const StickTable> sticks) {
  if (geometry.levels <= 0) geometry.levels = geometry.maxLevels();
  if (!stickId.empty()) {
    const std::uint32_t entries = sticks ? sticks->size() : 0;
    const auto bad = std::find_if(stickId.begin(), stickId.end(), [&](std::uint32_t id) { return id > entries; });
    if (bad != stickId.end()) {
      throw std::invalid_argument("MemoryTerrain: stick id " + std::to_string(*bad) + " with " +
                                  std::to_string(entries) + " table entries");
    }
  }
  mView = std::make_unique<TerrainView>(geometry, std::move(sticks));
  const std::vector<PyramidLevel> pyramid = buildPyramid(geometry, heightQ, colourRgba, stickId);
  const auto tileVoxels = static_cast<std::size_t>(geometry.tileSizeVox()) * geometry.tileSizeVox();
  for (int level = 0; level < geometry.levels; ++level) {
    for (int ty = 0; ty < geometry.tilesY(level); ++ty) {
      for (int tx = 0; tx < geometry.tilesX(level); ++tx) {
        auto owned = std::make_unique<OwnedTile>();
        owned->heightQ.resize(tileVoxels);
        owned->maxHeightQ.resize(tileVoxels);
        owned->colourRgba.resize(tileVoxels);
        owned->stickId.resize(stickId.empty() ? 0 : tileVoxels);
        cutTile(pyramid[static_cast<std::size_t>(level)], geometry.tileShift, tx, ty, owned->heightQ, owned->maxHeightQ,
                owned->colourRgba, owned->stickId);
        if (std::all_of(owned->stickId.begin(), owned->stickId.end(), [](std::uint32_t id) { return id == 0; })) {
          owned->stickId.clear();  // a tile without sticks says so with a null array
        }
        owned->tile = TerrainTile{owned->heightQ.data(), owned->maxHeightQ.data(), owned->colourRgba.data(),
                                  owned->stickId.empty() ? nullptr : owned->stickId.data()};
        mView->publish(level, tx, ty, &owned->tile);
        mTiles.push_back(std::move(owned));
      }
    }
  }
}

}  // namespace fieldcast::core
