#include <ig_core/TerrainView.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fieldcast::core {

int TerrainGeometry::maxLevels() const noexcept {
  int count = 1;
  while (levelWidthVox(count - 1) > tileSizeVox() || levelHeightVox(count - 1) > tileSizeVox()) {
    ++count;
  }
  return count;
}

TerrainView::TerrainView(const TerrainGeometry& geometry, std::shared_ptr<const StickTable> sticks)
    : mGeometry(geometry), mSticks(std::move(sticks)) {
  if (geometry.widthVox <= 0 || geometry.heightVox <= 0 || geometry.levels < 1 || geometry.levels > 24 ||
      geometry.tileShift < 2 || geometry.tileShift > 14 || !(geometry.spacingM > 0.0) ||
      !(geometry.heightStepM > 0.0)) {
    throw std::invalid_argument("TerrainView: invalid geometry " + std::to_string(geometry.widthVox) + "x" +
                                std::to_string(geometry.heightVox) + ", " + std::to_string(geometry.levels) +
                                " levels, tile shift " + std::to_string(geometry.tileShift));
  }
  mLevels.resize(static_cast<std::size_t>(geometry.levels));
  for (int level = 0; level < geometry.levels; ++level) {
    Level& l = mLevels[static_cast<std::size_t>(level)];
    l.tilesX = geometry.tilesX(level);
    l.tilesY = geometry.tilesY(level);
    const auto count = static_cast<std::size_t>(l.tilesX) * static_cast<std::size_t>(l.tilesY);
    l.slots = std::make_unique<std::atomic<const TerrainTile*>[]>(count);
    for (std::size_t k = 0; k < count; ++k) l.slots[k].store(nullptr, std::memory_order_relaxed);
  }
}

std::vector<std::uint64_t> stickBitsOf(std::span<const std::uint32_t> stickId) {
  std::vector<std::uint64_t> bits((stickId.size() + 63) / 64, 0);
  for (std::size_t k = 0; k < stickId.size(); ++k)
    if (stickId[k] != 0) bits[k >> 6] |= std::uint64_t{1} << (k & 63);
  return bits;
}

TerrainView::Sample TerrainView::sample(int level, int i, int j) const noexcept {
  for (int l = level; l < mGeometry.levels; ++l) {
    const int shift = l - level;
    const int li = std::clamp(i >> shift, 0, mGeometry.levelWidthVox(l) - 1);
    const int lj = std::clamp(j >> shift, 0, mGeometry.levelHeightVox(l) - 1);
    const TerrainTile* t = tile(l, li >> mGeometry.tileShift, lj >> mGeometry.tileShift);
    if (t == nullptr) continue;
    const int mask = mGeometry.tileSizeVox() - 1;
    const auto index = static_cast<std::size_t>(((lj & mask) << mGeometry.tileShift) | (li & mask));
    if (l != level) mMisses.fetch_add(1, std::memory_order_relaxed);
    return Sample{t->heightQ[index], t->maxHeightQ[index], t->colourRgba[index],
                  t->stickId != nullptr ? t->stickId[index] : 0u, l};
  }
  // The top level is always resident; reaching here means an owner broke that promise.
  mMisses.fetch_add(1, std::memory_order_relaxed);
  return Sample{0, 0, 0, 0, mGeometry.levels - 1};
}

double TerrainView::heightAtM(double xM, double yM, int level) const noexcept {
  const double cell = mGeometry.spacingM * static_cast<double>(1 << level);
  // Continuous index of the level's voxel centres (see the grid note in the header).
  const double half = 0.5 * static_cast<double>((1 << level) - 1) * mGeometry.spacingM;
  const double fi = (xM - mGeometry.originM.x - half) / cell;
  const double fj = (yM - mGeometry.originM.y - half) / cell;
  const double i0 = std::floor(fi);
  const double j0 = std::floor(fj);
  const double tx = fi - i0;
  const double ty = fj - j0;
  const int i = static_cast<int>(std::clamp(i0, -1.0, 1e9));
  const int j = static_cast<int>(std::clamp(j0, -1.0, 1e9));
  const double h00 = heightQ(level, i, j);
  const double h10 = heightQ(level, i + 1, j);
  const double h01 = heightQ(level, i, j + 1);
  const double h11 = heightQ(level, i + 1, j + 1);
  const double q = (h00 * (1 - tx) + h10 * tx) * (1 - ty) + (h01 * (1 - tx) + h11 * tx) * ty;
  return mGeometry.heightBaseM + mGeometry.heightStepM * q;
}

void TerrainView::publish(int level, int tx, int ty, const TerrainTile* tile) noexcept {
  Level& l = mLevels[static_cast<std::size_t>(level)];
  // seq_cst, not release: see tile() and TileCache::lease().
  l.slots[static_cast<std::size_t>(ty * l.tilesX + tx)].store(tile, std::memory_order_seq_cst);
}

}  // namespace fieldcast::core
