// libFuzzer target for the terrain database reader: the input is a whole database file. Inputs of
// even length get their checksums repaired first, so the fuzzer gets past them into the header
// field checks, the index bounds and the tile decoder; odd lengths exercise the checksums.
#include <ig_core/TerrainDatabase.h>

#include <xxhash.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

namespace {

using namespace fieldcast::core;

void repairChecksums(std::vector<std::byte>& file) {
  if (file.size() < kDatabaseHeaderBytes) return;
  std::uint64_t tileCount = 0;
  std::memcpy(&tileCount, file.data() + 80, 8);
  const std::uint64_t room = (file.size() - kDatabaseHeaderBytes) / kTileIndexEntryBytes;
  const std::uint64_t entries = std::min(tileCount, room);
  for (std::uint64_t k = 0; k < entries; ++k) {
    std::byte* e = file.data() + kDatabaseHeaderBytes + k * kTileIndexEntryBytes;
    std::uint64_t offset = 0;
    std::uint32_t bytes = 0;
    std::memcpy(&offset, e, 8);
    std::memcpy(&bytes, e + 8, 4);
    if (offset <= file.size() && bytes <= file.size() - offset) {
      const std::uint64_t sum = XXH3_64bits(file.data() + offset, bytes);
      std::memcpy(e + 16, &sum, 8);
    }
  }
  // Version 2: the checksum covers the georeference after the index too; version 3 the stick table.
  std::uint32_t version = 0, georeferenceBytes = 0, stickTableBytes = 0;
  std::memcpy(&version, file.data() + 8, 4);
  if (version >= 2) std::memcpy(&georeferenceBytes, file.data() + 112, 4);
  if (version >= 3) std::memcpy(&stickTableBytes, file.data() + 116, 4);
  const std::uint64_t covered =
      std::min<std::uint64_t>(entries * kTileIndexEntryBytes + std::uint64_t{georeferenceBytes} + stickTableBytes,
                              file.size() - kDatabaseHeaderBytes);
  const std::uint64_t indexSum = XXH3_64bits(file.data() + kDatabaseHeaderBytes, covered);
  std::memcpy(file.data() + 96, &indexSum, 8);
  const std::uint64_t headerSum = XXH3_64bits(file.data(), 120);
  std::memcpy(file.data() + 120, &headerSum, 8);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::byte> file(size);
  if (size > 0) std::memcpy(file.data(), data, size);
  if (size % 2 == 0) repairChecksums(file);
  const std::span<const std::byte> bytes(file);
  try {
    const DatabaseLayout layout = parseDatabaseHeader(bytes.first(std::min(size, kDatabaseHeaderBytes)), size, "fuzz");
    const std::size_t indexBytes = layout.tileCount * kTileIndexEntryBytes;
    const std::vector<TileIndexEntry> index =
        parseTileIndex(bytes.subspan(kDatabaseHeaderBytes, indexBytes), layout, "fuzz");
    (void)parseGeoreference(bytes.subspan(kDatabaseHeaderBytes + indexBytes, layout.georeferenceBytes), "fuzz");
    std::optional<StickTable> sticks;
    if (layout.stickTableBytes > 0) {
      sticks = StickTable::parse(
          bytes.subspan(kDatabaseHeaderBytes + indexBytes + layout.georeferenceBytes, layout.stickTableBytes));
    }
    TileBuffers tile;
    for (std::size_t k = 0; k < std::min<std::size_t>(index.size(), 4); ++k) {
      try {
        decodeTile(bytes.subspan(index[k].offset, index[k].compressedBytes), index[k], layout.geometry.tileShift,
                   layout.voxelColour, tile, "fuzz tile", tileSticks(layout, sticks ? &*sticks : nullptr));
        if (sticks) {
          // What a renderer reads of a stick voxel: its colours at the tile's level
          for (const std::uint32_t id : tile.stickId)
            if (id != 0) (void)sticks->colourBelowTop(id, 1, 3.5);
        }
      } catch (const TerrainDatabaseError&) {
      }
    }
  } catch (const TerrainDatabaseError&) {
  } catch (const StickTableError&) {
  }
  return 0;
}
