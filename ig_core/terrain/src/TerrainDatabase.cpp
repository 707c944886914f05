// The terrain database file: header, tile index and tile codec (format in ig_core/README.md).
#include <ig_core/TerrainDatabase.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>
#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

namespace fieldcast::core {

static_assert(std::endian::native == std::endian::little, "the database is little-endian; add byte swaps");

namespace {

// Header field offsets (bytes); see ig_core/README.md.
constexpr std::size_t kOffMagic = 0;
constexpr std::size_t kOffVersion = 8;
constexpr std::size_t kOffHeaderBytes = 12;
constexpr std::size_t kOffWidth = 16;
constexpr std::size_t kOffHeight = 20;
constexpr std::size_t kOffSpacing = 24;
constexpr std::size_t kOffOriginX = 32;
constexpr std::size_t kOffOriginY = 40;
constexpr std::size_t kOffHeightBase = 48;
constexpr std::size_t kOffHeightStep = 56;
constexpr std::size_t kOffTileShift = 64;
constexpr std::size_t kOffLevels = 68;
constexpr std::size_t kOffColourMode = 72;
constexpr std::size_t kOffTileEncoding = 76;
constexpr std::size_t kOffTileCount = 80;
constexpr std::size_t kOffIndexOffset = 88;
constexpr std::size_t kOffIndexChecksum = 96;
constexpr std::size_t kOffFileBytes = 104;
constexpr std::size_t kOffGeoreferenceBytes = 112;  // version 2; reserved (0) in version 1
constexpr std::size_t kOffStickTableBytes = 116;    // version 3; reserved (0) before
constexpr std::size_t kOffHeaderChecksum = 120;
constexpr std::uint32_t kTileEncodingDeltaZstd = 1;

template <typename T>
T load(std::span<const std::byte> bytes, std::size_t offset) noexcept {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

template <typename T>
void store(std::span<std::byte> bytes, std::size_t offset, T value) noexcept {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

std::uint64_t xxh3(std::span<const std::byte> bytes) noexcept { return XXH3_64bits(bytes.data(), bytes.size()); }

[[noreturn]] void fail(const std::string& fileName, const std::string& reason) {
  throw TerrainDatabaseError(fileName + ": " + reason);
}

std::string systemError(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

bool finiteWithin(double value, double lo, double hi) noexcept {
  return std::isfinite(value) && value >= lo && value <= hi;
}

// Delta coding along rows: each value becomes its difference from its left neighbour (mod 2^bits).
// Smooth terrain turns into small numbers that zstd packs tightly.
template <typename T>
void deltaEncodeRows(T* plane, int side) noexcept {
  for (int y = 0; y < side; ++y) {
    T* row = plane + static_cast<std::size_t>(y) * static_cast<std::size_t>(side);
    for (int x = side - 1; x > 0; --x) row[x] = static_cast<T>(row[x] - row[x - 1]);
  }
}

template <typename T>
void deltaDecodeRows(T* plane, int side) noexcept {
  for (int y = 0; y < side; ++y) {
    T* row = plane + static_cast<std::size_t>(y) * static_cast<std::size_t>(side);
    for (int x = 1; x < side; ++x) row[x] = static_cast<T>(row[x] + row[x - 1]);
  }
}

std::uint8_t greyOf(std::uint32_t rgba) noexcept {
  const std::uint32_t r = rgba & 0xFFu;
  const std::uint32_t g = (rgba >> 8) & 0xFFu;
  const std::uint32_t b = (rgba >> 16) & 0xFFu;
  return static_cast<std::uint8_t>((77u * r + 150u * g + 29u * b + 128u) >> 8);  // Rec. 601 luma
}

}  // namespace

void TileBuffers::resize(int tileShift) {
  const std::size_t n = std::size_t{1} << (2 * tileShift);
  heightQ.resize(n);
  maxHeightQ.resize(n);
  colourRgba.resize(n);
  stickId.clear();
  stickBits.clear();
}

TileSticks tileSticks(const DatabaseLayout& layout, const StickTable* table) noexcept {
  return TileSticks{layout.version >= 3, table != nullptr ? table->size() : 0u};
}

std::uint64_t totalTileCount(const TerrainGeometry& geometry) noexcept {
  std::uint64_t count = 0;
  for (int level = 0; level < geometry.levels; ++level) {
    count += static_cast<std::uint64_t>(geometry.tilesX(level)) * static_cast<std::uint64_t>(geometry.tilesY(level));
  }
  return count;
}

std::uint64_t tileIndexPosition(const TerrainGeometry& geometry, int level, int tx, int ty) noexcept {
  std::uint64_t before = 0;
  for (int l = 0; l < level; ++l) {
    before += static_cast<std::uint64_t>(geometry.tilesX(l)) * static_cast<std::uint64_t>(geometry.tilesY(l));
  }
  return before + static_cast<std::uint64_t>(ty) * static_cast<std::uint64_t>(geometry.tilesX(level)) +
         static_cast<std::uint64_t>(tx);
}

std::size_t rawTileBytes(int tileShift, VoxelColour mode, bool stickPlane) noexcept {
  const std::size_t n = std::size_t{1} << (2 * tileShift);
  return n * (2 + 2 + (mode == VoxelColour::Rgba ? 4 : 1) + (stickPlane ? 4 : 0));
}

DatabaseLayout parseDatabaseHeader(std::span<const std::byte> header, std::uint64_t actualFileBytes,
                                   const std::string& fileName) {
  if (header.size() < kDatabaseHeaderBytes || actualFileBytes < kDatabaseHeaderBytes) {
    fail(fileName, "truncated: " + std::to_string(actualFileBytes) + " bytes, a terrain database header needs " +
                       std::to_string(kDatabaseHeaderBytes));
  }
  if (std::memcmp(header.data() + kOffMagic, kDatabaseMagic, sizeof kDatabaseMagic) != 0) {
    fail(fileName, "not a Fieldcast terrain database (wrong magic; expected \"FCTERRDB\")");
  }
  const auto version = load<std::uint32_t>(header, kOffVersion);
  if (version < kOldestDatabaseVersion || version > kDatabaseVersion) {
    fail(fileName, "unsupported database version " + std::to_string(version) + " (this build reads versions " +
                       std::to_string(kOldestDatabaseVersion) + " to " + std::to_string(kDatabaseVersion) + ")");
  }
  if (load<std::uint64_t>(header, kOffHeaderChecksum) != xxh3(header.first(kOffHeaderChecksum))) {
    fail(fileName, "header checksum mismatch (corrupt header)");
  }
  if (load<std::uint32_t>(header, kOffHeaderBytes) != kDatabaseHeaderBytes) {
    fail(fileName, "header size " + std::to_string(load<std::uint32_t>(header, kOffHeaderBytes)) + ", expected " +
                       std::to_string(kDatabaseHeaderBytes));
  }
  DatabaseLayout layout;
  layout.version = version;
  TerrainGeometry& g = layout.geometry;
  const auto width = load<std::uint32_t>(header, kOffWidth);
  const auto height = load<std::uint32_t>(header, kOffHeight);
  if (width < 1 || height < 1 || width > kMaxDatabaseSideVox || height > kMaxDatabaseSideVox) {
    fail(fileName, "absurd grid size " + std::to_string(width) + "x" + std::to_string(height) + " (each side 1.." +
                       std::to_string(kMaxDatabaseSideVox) + ")");
  }
  g.widthVox = static_cast<int>(width);
  g.heightVox = static_cast<int>(height);
  g.spacingM = load<double>(header, kOffSpacing);
  g.originM = {load<double>(header, kOffOriginX), load<double>(header, kOffOriginY)};
  g.heightBaseM = load<double>(header, kOffHeightBase);
  g.heightStepM = load<double>(header, kOffHeightStep);
  if (!finiteWithin(g.spacingM, 1e-3, 1e5)) fail(fileName, "voxel spacing out of range (1 mm .. 100 km)");
  if (!finiteWithin(g.originM.x, -1e9, 1e9) || !finiteWithin(g.originM.y, -1e9, 1e9)) {
    fail(fileName, "origin is not a finite position within 10^9 m");
  }
  if (!finiteWithin(g.heightBaseM, -1e6, 1e6) || !finiteWithin(g.heightStepM, 1e-6, 1e3)) {
    fail(fileName, "height quantisation out of range (base within 10^6 m, step 1 um .. 1 km)");
  }
  const auto tileShift = load<std::uint32_t>(header, kOffTileShift);
  if (tileShift < kMinTileShift || tileShift > kMaxTileShift) {
    fail(fileName, "tile shift " + std::to_string(tileShift) + " out of range " + std::to_string(kMinTileShift) + ".." +
                       std::to_string(kMaxTileShift));
  }
  g.tileShift = static_cast<int>(tileShift);
  g.levels = 1;
  const auto levels = load<std::uint32_t>(header, kOffLevels);
  if (levels != static_cast<std::uint32_t>(g.maxLevels())) {
    fail(fileName, "level count " + std::to_string(levels) + " does not match the grid (expected " +
                       std::to_string(g.maxLevels()) + ")");
  }
  g.levels = static_cast<int>(levels);
  const auto voxelColour = load<std::uint32_t>(header, kOffColourMode);
  if (voxelColour > 1) fail(fileName, "unknown colour mode " + std::to_string(voxelColour));
  layout.voxelColour = static_cast<VoxelColour>(voxelColour);
  if (load<std::uint32_t>(header, kOffTileEncoding) != kTileEncodingDeltaZstd) {
    fail(fileName, "unknown tile encoding " + std::to_string(load<std::uint32_t>(header, kOffTileEncoding)));
  }
  layout.tileCount = load<std::uint64_t>(header, kOffTileCount);
  if (layout.tileCount != totalTileCount(g)) {
    fail(fileName, "tile count " + std::to_string(layout.tileCount) + " does not match the grid (expected " +
                       std::to_string(totalTileCount(g)) + ")");
  }
  if (load<std::uint64_t>(header, kOffIndexOffset) != kDatabaseHeaderBytes) {
    fail(fileName, "tile index offset " + std::to_string(load<std::uint64_t>(header, kOffIndexOffset)) + ", expected " +
                       std::to_string(kDatabaseHeaderBytes));
  }
  layout.fileBytes = load<std::uint64_t>(header, kOffFileBytes);
  if (layout.fileBytes != actualFileBytes) {
    fail(fileName, "truncated or extended: the header says " + std::to_string(layout.fileBytes) +
                       " bytes, the file has " + std::to_string(actualFileBytes));
  }
  if (layout.tileCount > (layout.fileBytes - kDatabaseHeaderBytes) / kTileIndexEntryBytes) {
    fail(fileName, "tile index of " + std::to_string(layout.tileCount) + " entries does not fit in the file");
  }
  if (version >= 2) {
    layout.georeferenceBytes = load<std::uint32_t>(header, kOffGeoreferenceBytes);
    if (layout.georeferenceBytes > kMaxGeoreferenceBytes) {
      fail(fileName, "georeference of " + std::to_string(layout.georeferenceBytes) + " bytes (at most " +
                         std::to_string(kMaxGeoreferenceBytes) + ")");
    }
    if (layout.georeferenceBytes > layout.fileBytes - kDatabaseHeaderBytes - layout.tileCount * kTileIndexEntryBytes) {
      fail(fileName, "georeference of " + std::to_string(layout.georeferenceBytes) + " bytes does not fit in the file");
    }
  }
  if (version >= 3) {
    layout.stickTableBytes = load<std::uint32_t>(header, kOffStickTableBytes);
    if (layout.stickTableBytes > kMaxStickTableBytes) {
      fail(fileName, "stick table of " + std::to_string(layout.stickTableBytes) + " bytes (at most " +
                         std::to_string(kMaxStickTableBytes) + ")");
    }
    if (layout.stickTableBytes >
        layout.fileBytes - kDatabaseHeaderBytes - layout.tileCount * kTileIndexEntryBytes - layout.georeferenceBytes) {
      fail(fileName, "stick table of " + std::to_string(layout.stickTableBytes) + " bytes does not fit in the file");
    }
  }
  return layout;
}

std::vector<TileIndexEntry> parseTileIndex(std::span<const std::byte> index, const DatabaseLayout& layout,
                                           const std::string& fileName) {
  const std::uint64_t indexBytes = layout.tileCount * kTileIndexEntryBytes;
  if (index.size() != indexBytes) {
    fail(fileName, "tile index is " + std::to_string(index.size()) + " bytes, expected " + std::to_string(indexBytes));
  }
  const std::uint64_t dataStart = kDatabaseHeaderBytes + indexBytes + layout.georeferenceBytes + layout.stickTableBytes;
  const std::size_t maxCompressed =
      ZSTD_compressBound(rawTileBytes(layout.geometry.tileShift, layout.voxelColour, layout.version >= 3));
  std::vector<TileIndexEntry> entries(static_cast<std::size_t>(layout.tileCount));
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const std::span<const std::byte> raw = index.subspan(k * kTileIndexEntryBytes, kTileIndexEntryBytes);
    TileIndexEntry& e = entries[k];
    e.offset = load<std::uint64_t>(raw, 0);
    e.compressedBytes = load<std::uint32_t>(raw, 8);
    e.checksum = load<std::uint64_t>(raw, 16);
    if (e.compressedBytes == 0 || e.compressedBytes > maxCompressed || e.offset < dataStart ||
        e.offset > layout.fileBytes || e.compressedBytes > layout.fileBytes - e.offset) {
      fail(fileName, "tile index entry " + std::to_string(k) + " points outside the tile data (offset " +
                         std::to_string(e.offset) + ", " + std::to_string(e.compressedBytes) + " bytes)");
    }
  }
  return entries;
}

std::vector<std::byte> serializeTileIndex(std::span<const TileIndexEntry> entries) {
  std::vector<std::byte> bytes(entries.size() * kTileIndexEntryBytes);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const std::span<std::byte> raw = std::span(bytes).subspan(k * kTileIndexEntryBytes, kTileIndexEntryBytes);
    store<std::uint64_t>(raw, 0, entries[k].offset);
    store<std::uint32_t>(raw, 8, entries[k].compressedBytes);
    store<std::uint32_t>(raw, 12, 0);
    store<std::uint64_t>(raw, 16, entries[k].checksum);
  }
  return bytes;
}

std::string parseGeoreference(std::span<const std::byte> block, const std::string& fileName) {
  std::string text(block.size(), '\0');
  for (std::size_t k = 0; k < block.size(); ++k) {
    const auto c = static_cast<unsigned char>(block[k]);
    if (c < 0x20 || c == 0x7F) {
      fail(fileName, "georeference holds a control character at byte " + std::to_string(k) + " (corrupt?)");
    }
    text[k] = static_cast<char>(c);
  }
  return text;
}

std::vector<std::byte> serializeDatabaseHeader(const DatabaseLayout& layout, std::span<const std::byte> metadata) {
  std::vector<std::byte> header(kDatabaseHeaderBytes, std::byte{0});
  const std::span<std::byte> h(header);
  const TerrainGeometry& g = layout.geometry;
  std::memcpy(h.data() + kOffMagic, kDatabaseMagic, sizeof kDatabaseMagic);
  store<std::uint32_t>(h, kOffVersion, kDatabaseVersion);
  store<std::uint32_t>(h, kOffHeaderBytes, static_cast<std::uint32_t>(kDatabaseHeaderBytes));
  store<std::uint32_t>(h, kOffWidth, static_cast<std::uint32_t>(g.widthVox));
  store<std::uint32_t>(h, kOffHeight, static_cast<std::uint32_t>(g.heightVox));
  store<double>(h, kOffSpacing, g.spacingM);
  store<double>(h, kOffOriginX, g.originM.x);
  store<double>(h, kOffOriginY, g.originM.y);
  store<double>(h, kOffHeightBase, g.heightBaseM);
  store<double>(h, kOffHeightStep, g.heightStepM);
  store<std::uint32_t>(h, kOffTileShift, static_cast<std::uint32_t>(g.tileShift));
  store<std::uint32_t>(h, kOffLevels, static_cast<std::uint32_t>(g.levels));
  store<std::uint32_t>(h, kOffColourMode, static_cast<std::uint32_t>(layout.voxelColour));
  store<std::uint32_t>(h, kOffTileEncoding, kTileEncodingDeltaZstd);
  store<std::uint64_t>(h, kOffTileCount, layout.tileCount);
  store<std::uint64_t>(h, kOffIndexOffset, kDatabaseHeaderBytes);
  store<std::uint64_t>(h, kOffIndexChecksum, xxh3(metadata));
  store<std::uint64_t>(h, kOffFileBytes, layout.fileBytes);
  store<std::uint32_t>(h, kOffGeoreferenceBytes, static_cast<std::uint32_t>(layout.crs.size()));
  store<std::uint32_t>(h, kOffStickTableBytes, layout.stickTableBytes);
  store<std::uint64_t>(h, kOffHeaderChecksum, xxh3(std::span<const std::byte>(header).first(kOffHeaderChecksum)));
  return header;
}

std::vector<std::byte> encodeTile(const TileBuffers& tile, int tileShift, VoxelColour mode, int zstdLevel) {
  const int side = 1 << tileShift;
  const std::size_t n = std::size_t{1} << (2 * tileShift);
  std::vector<std::byte> raw(rawTileBytes(tileShift, mode));
  auto* heights = reinterpret_cast<std::uint16_t*>(raw.data());
  auto* maxima = heights + n;
  std::memcpy(heights, tile.heightQ.data(), n * 2);
  std::memcpy(maxima, tile.maxHeightQ.data(), n * 2);
  deltaEncodeRows(heights, side);
  deltaEncodeRows(maxima, side);
  auto* planes = reinterpret_cast<std::uint8_t*>(maxima + n);
  if (mode == VoxelColour::Rgba) {
    for (int c = 0; c < 4; ++c) {
      std::uint8_t* plane = planes + static_cast<std::size_t>(c) * n;
      for (std::size_t k = 0; k < n; ++k) plane[k] = static_cast<std::uint8_t>(tile.colourRgba[k] >> (8 * c));
      deltaEncodeRows(plane, side);
    }
  } else {
    for (std::size_t k = 0; k < n; ++k) planes[k] = greyOf(tile.colourRgba[k]);
    deltaEncodeRows(planes, side);
  }
  // Stick ids: runs of one id (a roof, a wood of one species) delta-code to zeros
  std::byte* sticks = raw.data() + raw.size() - 4 * n;
  if (tile.stickId.empty()) {
    std::memset(sticks, 0, 4 * n);
  } else {
    std::vector<std::uint32_t> ids(tile.stickId.begin(), tile.stickId.begin() + static_cast<std::ptrdiff_t>(n));
    deltaEncodeRows(ids.data(), side);
    std::memcpy(sticks, ids.data(), 4 * n);
  }
  std::vector<std::byte> compressed(ZSTD_compressBound(raw.size()));
  const std::size_t size = ZSTD_compress(compressed.data(), compressed.size(), raw.data(), raw.size(), zstdLevel);
  if (ZSTD_isError(size) != 0u) throw TerrainDatabaseError(std::string("zstd: ") + ZSTD_getErrorName(size));
  compressed.resize(size);
  return compressed;
}

void decodeTile(std::span<const std::byte> compressed, const TileIndexEntry& entry, int tileShift, VoxelColour mode,
                TileBuffers& out, const std::string& what, TileSticks sticks) {
  if (compressed.size() != entry.compressedBytes) {
    fail(what,
         "expected " + std::to_string(entry.compressedBytes) + " bytes, read " + std::to_string(compressed.size()));
  }
  if (xxh3(compressed) != entry.checksum) fail(what, "checksum mismatch (corrupt tile)");
  const std::size_t expected = rawTileBytes(tileShift, mode, sticks.plane);
  const unsigned long long content = ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (content != expected) fail(what, "tile does not decode to " + std::to_string(expected) + " bytes");
  thread_local std::vector<std::byte> raw;
  thread_local std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> context(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  raw.resize(expected);
  const std::size_t size =
      ZSTD_decompressDCtx(context.get(), raw.data(), raw.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(size) != 0u || size != expected) {
    fail(what, std::string("tile does not decompress: ") +
                   (ZSTD_isError(size) != 0u ? ZSTD_getErrorName(size) : "wrong length"));
  }
  const int side = 1 << tileShift;
  const std::size_t n = std::size_t{1} << (2 * tileShift);
  out.resize(tileShift);
  auto* heights = reinterpret_cast<std::uint16_t*>(raw.data());
  auto* maxima = heights + n;
  deltaDecodeRows(heights, side);
  deltaDecodeRows(maxima, side);
  std::memcpy(out.heightQ.data(), heights, n * 2);
  std::memcpy(out.maxHeightQ.data(), maxima, n * 2);
  auto* planes = reinterpret_cast<std::uint8_t*>(maxima + n);
  if (mode == VoxelColour::Rgba) {
    for (int c = 0; c < 4; ++c) deltaDecodeRows(planes + static_cast<std::size_t>(c) * n, side);
    for (std::size_t k = 0; k < n; ++k) {
      out.colourRgba[k] = std::uint32_t{planes[k]} | (std::uint32_t{planes[n + k]} << 8) |
                          (std::uint32_t{planes[2 * n + k]} << 16) | (std::uint32_t{planes[3 * n + k]} << 24);
    }
  } else {
    deltaDecodeRows(planes, side);
    for (std::size_t k = 0; k < n; ++k) out.colourRgba[k] = planes[k] * 0x010101u | 0xFF000000u;
  }
  if (!sticks.plane) return;
  out.stickId.resize(n);
  std::memcpy(out.stickId.data(), raw.data() + raw.size() - 4 * n, 4 * n);
  deltaDecodeRows(out.stickId.data(), side);
  std::uint32_t highest = 0;
  for (const std::uint32_t id : out.stickId) highest = std::max(highest, id);
  if (highest > sticks.entries) {
    fail(what, "stick id " + std::to_string(highest) + " beyond the stick table's " + std::to_string(sticks.entries) +
                   " entries (corrupt tile)");
  }
  if (highest == 0) out.stickId.clear();  // no stick in this tile
}

// ---------------------------------------------------------------------------------------------
// Reader

namespace {

void readExactly(int fd, std::uint64_t offset, std::span<std::byte> out, const std::string& fileName) {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(fileName, systemError("read failed"));
    if (n == 0) fail(fileName, "unexpected end of file at byte " + std::to_string(offset + done));
    done += static_cast<std::size_t>(n);
  }
}

// ".<name>.tmp-<pid><suffix>" beside the target (built by appending: GCC 12 warns falsely on "." + s).
std::string temporaryName(const std::filesystem::path& target, const std::string& suffix) {
  std::string name = ".";
  name += target.filename().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += suffix;
  return name;
}

}  // namespace

DatabaseReader::DatabaseReader(const std::filesystem::path& path) : mPath(path) {
  const std::string name = path.string();
  mFd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (mFd < 0) fail(name, systemError("cannot open terrain database"));
  try {
    struct stat st {};
    if (::fstat(mFd, &st) != 0) fail(name, systemError("cannot stat"));
    if (!S_ISREG(st.st_mode)) fail(name, "not a regular file");
    const auto fileBytes = static_cast<std::uint64_t>(st.st_size);
    std::vector<std::byte> header(kDatabaseHeaderBytes);
    if (fileBytes < kDatabaseHeaderBytes) {
      fail(name, "truncated: " + std::to_string(fileBytes) + " bytes, a terrain database header needs " +
                     std::to_string(kDatabaseHeaderBytes));
    }
    readExactly(mFd, 0, header, name);
    mLayout = parseDatabaseHeader(header, fileBytes, name);
    // parseDatabaseHeader has checked that the index, the georeference and the stick table fit
    // inside the file.
    const auto indexBytes = static_cast<std::size_t>(mLayout.tileCount * kTileIndexEntryBytes);
    std::vector<std::byte> metadata(indexBytes + mLayout.georeferenceBytes + mLayout.stickTableBytes);
    readExactly(mFd, kDatabaseHeaderBytes, metadata, name);
    if (xxh3(metadata) != load<std::uint64_t>(header, kOffIndexChecksum)) {
      fail(name, mLayout.georeferenceBytes + mLayout.stickTableBytes > 0
                     ? "tile index, georeference or stick table checksum mismatch (corrupt index)"
                     : "tile index checksum mismatch (corrupt index)");
    }
    const std::span<const std::byte> all(metadata);
    mIndex = parseTileIndex(all.first(indexBytes), mLayout, name);
    mLayout.crs = parseGeoreference(all.subspan(indexBytes, mLayout.georeferenceBytes), name);
    if (mLayout.stickTableBytes > 0) {
      try {
        mSticks = std::make_shared<const StickTable>(
            StickTable::parse(all.subspan(indexBytes + mLayout.georeferenceBytes, mLayout.stickTableBytes)));
      } catch (const StickTableError& e) {
        fail(name, e.what());
      }
    }
  } catch (...) {
    ::close(mFd);
    throw;
  }
}

DatabaseReader::~DatabaseReader() {
  if (mFd >= 0) ::close(mFd);
}

std::uint64_t DatabaseReader::compressedBytes() const noexcept {
  std::uint64_t sum = 0;
  for (const TileIndexEntry& e : mIndex) sum += e.compressedBytes;
  return sum;
}

void DatabaseReader::readTile(int level, int tx, int ty, TileBuffers& out) const {
  const TileIndexEntry& e = entry(level, tx, ty);
  std::ostringstream what;
  what << mPath.string() << ": tile L" << level << " (" << tx << ", " << ty << ")";
  thread_local std::vector<std::byte> compressed;
  compressed.resize(e.compressedBytes);
  readExactly(mFd, e.offset, compressed, what.str());
  decodeTile(compressed, e, mLayout.geometry.tileShift, mLayout.voxelColour, out, what.str(),
             tileSticks(mLayout, mSticks.get()));
}

// ---------------------------------------------------------------------------------------------
// Writer

DatabaseWriter::DatabaseWriter(std::filesystem::path path, const DatabaseLayout& layout, const StickTable* sticks)
    : mPath(std::move(path)), mLayout(layout) {
  const std::string name = mPath.string();
  if (mLayout.geometry.levels != mLayout.geometry.maxLevels()) {
    fail(name, "a database stores every level down to one tile (" + std::to_string(mLayout.geometry.maxLevels()) +
                   "), got " + std::to_string(mLayout.geometry.levels));
  }
  if (mLayout.crs.size() > kMaxGeoreferenceBytes) {
    fail(name, "georeference of " + std::to_string(mLayout.crs.size()) + " bytes (at most " +
                   std::to_string(kMaxGeoreferenceBytes) + ")");
  }
  // The writer's own check of what the reader will refuse.
  (void)parseGeoreference(std::as_bytes(std::span(mLayout.crs)), name);
  if (sticks != nullptr && sticks->size() > 0) mStickTable = sticks->serialize();
  if (mStickTable.size() > kMaxStickTableBytes) {
    fail(name, "stick table of " + std::to_string(mStickTable.size()) + " bytes (at most " +
                   std::to_string(kMaxStickTableBytes) + ")");
  }
  mLayout.version = kDatabaseVersion;
  mLayout.georeferenceBytes = static_cast<std::uint32_t>(mLayout.crs.size());
  mLayout.stickTableBytes = static_cast<std::uint32_t>(mStickTable.size());
  mLayout.tileCount = totalTileCount(mLayout.geometry);
  mIndex.resize(static_cast<std::size_t>(mLayout.tileCount));
  mWritten.assign(mIndex.size(), false);
  mEnd = kDatabaseHeaderBytes + mLayout.tileCount * kTileIndexEntryBytes + mLayout.georeferenceBytes +
         mLayout.stickTableBytes;
  std::filesystem::path folder = mPath.parent_path();
  if (folder.empty()) folder = ".";
  // An unnamed file vanishes by itself if the build dies; it gets a name only once complete.
  mFd = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0644);
  if (mFd < 0) {
    mNamedTemp = folder / temporaryName(mPath, "");
    mFd = ::open(mNamedTemp.c_str(), O_CREAT | O_TRUNC | O_RDWR | O_CLOEXEC, 0644);
    if (mFd < 0) fail(name, systemError("cannot create a temporary file in its folder"));
  }
}

DatabaseWriter::~DatabaseWriter() {
  if (mFd >= 0) ::close(mFd);
  if (!mCommitted && !mNamedTemp.empty()) ::unlink(mNamedTemp.c_str());
}

void DatabaseWriter::writeAt(std::uint64_t offset, std::span<const std::byte> bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::pwrite(mFd, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(mPath.string(), systemError("write failed"));
    done += static_cast<std::size_t>(n);
  }
}

void DatabaseWriter::writeTile(int level, int tx, int ty, std::span<const std::byte> compressed) {
  const std::uint64_t k = tileIndexPosition(mLayout.geometry, level, tx, ty);
  if (k >= mIndex.size() || mWritten[k]) {
    fail(mPath.string(), "tile L" + std::to_string(level) + " (" + std::to_string(tx) + ", " + std::to_string(ty) +
                             ") written twice or out of range");
  }
  writeAt(mEnd, compressed);
  mIndex[k] = TileIndexEntry{mEnd, static_cast<std::uint32_t>(compressed.size()), xxh3(compressed)};
  mWritten[k] = true;
  mEnd += compressed.size();
}

std::uint64_t DatabaseWriter::commit() {
  const std::string name = mPath.string();
  for (std::size_t k = 0; k < mWritten.size(); ++k) {
    if (!mWritten[k]) fail(name, "tile " + std::to_string(k) + " was never written");
  }
  mLayout.fileBytes = mEnd;
  std::vector<std::byte> metadata = serializeTileIndex(mIndex);
  const std::span<const std::byte> crs = std::as_bytes(std::span(mLayout.crs));
  metadata.insert(metadata.end(), crs.begin(), crs.end());
  metadata.insert(metadata.end(), mStickTable.begin(), mStickTable.end());
  const std::vector<std::byte> header = serializeDatabaseHeader(mLayout, metadata);
  writeAt(kDatabaseHeaderBytes, metadata);
  writeAt(0, header);
  if (::fsync(mFd) != 0) fail(name, systemError("fsync failed"));
  if (mNamedTemp.empty()) {
    // Give the unnamed file a unique temporary name, then rename it over the target atomically.
    static std::atomic<unsigned> counter{0};
    const std::filesystem::path folder = mPath.parent_path().empty() ? "." : mPath.parent_path();
    mNamedTemp = folder / temporaryName(mPath, std::string(1, '-').append(std::to_string(counter.fetch_add(1))));
    const std::string procPath = std::string("/proc/self/fd/").append(std::to_string(mFd));
    if (::linkat(AT_FDCWD, procPath.c_str(), AT_FDCWD, mNamedTemp.c_str(), AT_SYMLINK_FOLLOW) != 0) {
      mNamedTemp.clear();
      fail(name, systemError("cannot link the finished temporary file"));
    }
  }
  if (::rename(mNamedTemp.c_str(), mPath.c_str()) != 0) {
    const std::string reason = systemError("cannot move the finished database into place");
    ::unlink(mNamedTemp.c_str());
    mNamedTemp.clear();
    fail(name, reason);
  }
  mCommitted = true;
  const std::filesystem::path folder = mPath.parent_path().empty() ? "." : mPath.parent_path();
  const int dirFd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dirFd >= 0) {
    (void)::fsync(dirFd);  // make the rename durable; best effort
    ::close(dirFd);
  }
  return mEnd;
}

}  // namespace fieldcast::core
