#pragma once
// The on-disk terrain database (format described in ig_core/README.md, "Database format"):
// a fixed 128-byte header, a tile index, the georeference (version 2), the stick table (version
// 3), then zstd-compressed tiles, each with an XXH3 checksum.
// Every level of the pyramid is stored, tile by tile; tiles hold the same arrays TerrainTile
// points at (heights, conservative max mip, colours).
//
// Reading validates everything before trusting it: magic, version, sizes within limits, header
// and index checksums, every index entry inside the file. No allocation is sized from a header
// field that the file's real length has not bounded first.

#include <ig_core/Sticks.h>
#include <ig_core/TerrainView.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::core {

/// A database file that cannot be read or written; what() names the file and what was wrong.
class TerrainDatabaseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How colours are stored: four channels, or one grey channel (expanded to RGBA when loaded).
enum class VoxelColour : std::uint8_t { Rgba = 0, Grey = 1 };

/// "FCTERRDB": the first eight bytes of every database.
inline constexpr char kDatabaseMagic[8] = {'F', 'C', 'T', 'E', 'R', 'R', 'D', 'B'};
/// Format version this code writes. Version 2 added the georeference (the CRS text after the index),
/// version 3 the sticks (the stick table after the georeference, a stick-id plane in every tile).
inline constexpr std::uint32_t kDatabaseVersion = 3;
/// Oldest version this code reads: version 1 files open with no georeference.
inline constexpr std::uint32_t kOldestDatabaseVersion = 1;
/// Longest georeference (CRS text) a database may hold, in bytes.
inline constexpr std::uint32_t kMaxGeoreferenceBytes = 64 * 1024;
/// Largest stick table a database may hold, in bytes.
inline constexpr std::uint32_t kMaxStickTableBytes = 64u << 20;
/// Size of the fixed header in bytes; the tile index follows it.
inline constexpr std::size_t kDatabaseHeaderBytes = 128;
/// Size of one tile index entry in bytes.
inline constexpr std::size_t kTileIndexEntryBytes = 24;
/// Largest level-0 side a database may declare (voxels).
inline constexpr int kMaxDatabaseSideVox = 1 << 18;
/// Tile sides a database may declare: 1 << kMinTileShift .. 1 << kMaxTileShift voxels.
inline constexpr int kMinTileShift = 4;
inline constexpr int kMaxTileShift = 11;

/// What the header says, after validation.
struct DatabaseLayout {
  TerrainGeometry geometry;  ///< levels and tile shift included
  VoxelColour voxelColour = VoxelColour::Rgba;
  std::uint32_t version = kDatabaseVersion;  ///< as read (the writer always writes kDatabaseVersion)
  /// The coordinate reference system of world x, y: "EPSG:n" or WKT (as PROJ reads it); empty when
  /// the database has no georeference (version 1 files, the built-in terrain, grids without one).
  /// World x, y are coordinates in this CRS; originM places the grid in it.
  std::string crs;
  std::uint32_t georeferenceBytes = 0;  ///< length of the CRS text in the file (parseDatabaseHeader)
  std::uint32_t stickTableBytes = 0;    ///< length of the stick table in the file (0: none; version 3)
  std::uint64_t tileCount = 0;          ///< all tiles of all levels
  std::uint64_t fileBytes = 0;          ///< the length the header promises
};

/// Where one tile lies in the file.
struct TileIndexEntry {
  std::uint64_t offset = 0;           ///< byte offset of the compressed tile
  std::uint32_t compressedBytes = 0;  ///< length of the compressed tile
  std::uint64_t checksum = 0;         ///< XXH3-64 of the compressed bytes
};

/// One decoded tile: tileSize² voxels of each array, row-major, like TerrainTile.
struct TileBuffers {
  std::vector<std::uint16_t> heightQ;
  std::vector<std::uint16_t> maxHeightQ;
  std::vector<std::uint32_t> colourRgba;
  std::vector<std::uint32_t> stickId;    ///< empty when the tile has no stick (all ids 0)
  std::vector<std::uint64_t> stickBits;  ///< TerrainTile::stickBits, made by whoever publishes the tile

  /// Sizes heights, maxima and colours for tiles of 1 << tileShift voxels a side (stick ids and
  /// their bits are left empty: no sticks).
  void resize(int tileShift);
};

/// What the tiles of a database say about sticks: whether they carry the stick-id plane (version 3)
/// and how many entries the table has (a tile's ids must not exceed it).
struct TileSticks {
  bool plane;
  std::uint32_t entries;
};
/// The tile sticks of a database of this layout.
TileSticks tileSticks(const DatabaseLayout& layout, const StickTable* table) noexcept;

/// Number of tiles over all levels of `geometry`.
std::uint64_t totalTileCount(const TerrainGeometry& geometry) noexcept;
/// Position of tile (level, tx, ty) in the index: level by level, rows north, tiles east.
std::uint64_t tileIndexPosition(const TerrainGeometry& geometry, int level, int tx, int ty) noexcept;
/// Bytes of one uncompressed tile in a database of this colour mode (with the stick-id plane of
/// version 3, or without).
std::size_t rawTileBytes(int tileShift, VoxelColour mode, bool stickPlane = true) noexcept;

/// Parses and validates the 128-byte header of `fileName` whose real length is `actualFileBytes`.
/// Throws TerrainDatabaseError naming the file and the field that is wrong.
DatabaseLayout parseDatabaseHeader(std::span<const std::byte> header, std::uint64_t actualFileBytes,
                                   const std::string& fileName);
/// Parses and validates the tile index (layout.tileCount entries; the tiles start after it and the
/// georeference). Throws TerrainDatabaseError.
std::vector<TileIndexEntry> parseTileIndex(std::span<const std::byte> index, const DatabaseLayout& layout,
                                           const std::string& fileName);
/// Checks the georeference block (layout.georeferenceBytes of text after the index: printable
/// ASCII/UTF-8, no control characters) and returns it as the CRS. Throws TerrainDatabaseError.
std::string parseGeoreference(std::span<const std::byte> block, const std::string& fileName);
/// Serialises `layout` into a header for the index, georeference and stick table bytes that follow
/// it (`metadata`, which the header's second checksum covers).
std::vector<std::byte> serializeDatabaseHeader(const DatabaseLayout& layout, std::span<const std::byte> metadata);
/// Serialises index entries.
std::vector<std::byte> serializeTileIndex(std::span<const TileIndexEntry> entries);

/// Compresses one tile (delta-coded planes, zstd at `zstdLevel`) as this version writes it, stick
/// ids included (zeros when the tile has none). Thread-safe.
std::vector<std::byte> encodeTile(const TileBuffers& tile, int tileShift, VoxelColour mode, int zstdLevel);
/// Checks the checksum and decodes one compressed tile into `out` (resized). `what` names the
/// tile in errors ("terrain.fctdb: tile L0 (3, 4)"). Throws TerrainDatabaseError, also for a
/// stick id beyond the table. Thread-safe.
void decodeTile(std::span<const std::byte> compressed, const TileIndexEntry& entry, int tileShift, VoxelColour mode,
                TileBuffers& out, const std::string& what, TileSticks sticks);

/// An open database: header and index validated, tiles read on demand with pread (thread-safe).
class DatabaseReader {
 public:
  /// Opens and validates `path`. Throws TerrainDatabaseError naming the file and the reason.
  explicit DatabaseReader(const std::filesystem::path& path);
  ~DatabaseReader();
  DatabaseReader(const DatabaseReader&) = delete;
  DatabaseReader& operator=(const DatabaseReader&) = delete;

  const DatabaseLayout& layout() const noexcept { return mLayout; }
  const TerrainGeometry& geometry() const noexcept { return mLayout.geometry; }
  /// The stick table, or nullptr when the database has none (versions 1 and 2, or no sticks).
  const std::shared_ptr<const StickTable>& sticks() const noexcept { return mSticks; }
  const std::filesystem::path& path() const noexcept { return mPath; }
  const TileIndexEntry& entry(int level, int tx, int ty) const noexcept {
    return mIndex[tileIndexPosition(mLayout.geometry, level, tx, ty)];
  }
  /// Sum of the compressed tile sizes in bytes.
  std::uint64_t compressedBytes() const noexcept;

  /// Reads, checks and decodes tile (level, tx, ty) into `out`. Throws TerrainDatabaseError on an
  /// I/O error, a checksum mismatch or a tile that does not decode. Thread-safe; not RT-safe.
  void readTile(int level, int tx, int ty, TileBuffers& out) const;

 private:
  std::filesystem::path mPath;
  int mFd = -1;
  DatabaseLayout mLayout;
  std::shared_ptr<const StickTable> mSticks;
  std::vector<TileIndexEntry> mIndex;
};

/// Writes a database atomically: tiles are appended to an unnamed temporary file in the target's
/// folder, and commit() writes the index and header, syncs, and moves the file into place. An
/// interrupted or abandoned write leaves nothing behind and never a half database at `path`.
class DatabaseWriter {
 public:
  /// Prepares to write `path` for `layout` (tileCount and fileBytes are filled in by commit()),
  /// with the stick table `sticks` (null: none; the tiles' ids must then all be 0).
  DatabaseWriter(std::filesystem::path path, const DatabaseLayout& layout, const StickTable* sticks = nullptr);
  ~DatabaseWriter();
  DatabaseWriter(const DatabaseWriter&) = delete;
  DatabaseWriter& operator=(const DatabaseWriter&) = delete;

  /// Appends the compressed tile (level, tx, ty). Every tile must be written exactly once, in any order.
  void writeTile(int level, int tx, int ty, std::span<const std::byte> compressed);
  /// Writes index and header, syncs, and atomically replaces `path`. Returns the file size.
  std::uint64_t commit();

 private:
  void writeAt(std::uint64_t offset, std::span<const std::byte> bytes);
  std::filesystem::path mPath;
  std::filesystem::path mNamedTemp;  // set only when the filesystem lacks O_TMPFILE
  int mFd = -1;
  DatabaseLayout mLayout;
  std::vector<std::byte> mStickTable;  // stored form
  std::vector<TileIndexEntry> mIndex;
  std::vector<bool> mWritten;
  std::uint64_t mEnd = 0;
  bool mCommitted = false;
};

}  // namespace fieldcast::core
