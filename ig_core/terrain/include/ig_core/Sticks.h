#pragma once
// Objects as sticks (DESIGN.md §2, ig_core/README.md "Sticks"): a voxel may carry a stick, a run of
// stick voxels standing on it — a hedge, a tree, a house's wall. The voxel's height is the top of
// its stick; which stick it is comes from a per-voxel id into the terrain's shared stick table, so
// a forest of one species or a town of one house type costs one table entry per kind of stick.
//
// A table entry holds the stick's colours from the top down, one per stick voxel of `unitM`
// metres (a uniform stick has one colour for all of it; a stick standing on lower ground than it
// was made for repeats its last colour down to the ground). Coarser pyramid levels read the same
// entry through its mips: level L's stick voxels are 2^L units tall, each the mean of the level-0
// colours it covers, so a façade's windows are filtered like the terrain's texels.

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::core {

/// What kind of stick a table entry is.
enum class StickKind : std::uint8_t {
  Uniform = 1,   ///< one colour over the whole run
  Textured = 2,  ///< a colour per stick voxel, top down
  /// Textured, with see-through stick voxels (alpha below 255): alpha 0 is a cavity (the gap under
  /// a crown, under a bridge's deck, between a van's wheels), 1 … 254 semi-transparent. A ray that
  /// meets one goes on as a secondary ray. Only level 0 sees through: the mips fill cavities.
  Complex = 3,
};

/// A complex stick's cavity texel (alpha 0: seen through), RGBA8.
inline constexpr std::uint32_t kCavityRgba = 0x00000000u;
/// The alpha bits of an opaque texel, RGBA8.
inline constexpr std::uint32_t kOpaqueRgba = 0xFF000000u;

/// Longest stick a table entry may describe, in stick voxels (at 0.5 m: a 2 km tower).
inline constexpr std::uint32_t kMaxStickLength = 4096;
/// Most entries a table may hold (stick ids are 1 .. this; 0 is "no stick"): a table holds a kind
/// of stick once, however often it stands, so a million is far more than any database needs, and
/// it bounds what a crafted file can make a reader allocate.
inline constexpr std::uint32_t kMaxStickEntries = 1u << 20;

/// A stick table that cannot be built or read; what() says what was wrong.
class StickTableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One entry as a database builder describes it.
struct StickEntry {
  StickKind kind = StickKind::Uniform;
  std::uint32_t lengthVox = 1;        ///< stick voxels from the top down (the length it was made for)
  std::vector<std::uint32_t> texels;  ///< RGBA8, top down: one for Uniform, lengthVox for the others
};

/// The shared stick table of a terrain: immutable once built, read lock-free by renderers.
class StickTable {
 public:
  /// A table of stick voxels `unitM` metres tall. Throws StickTableError on a unit outside
  /// 1 mm … 1 km, too many entries, or an entry whose texels do not match its kind and length.
  StickTable(double unitM, std::vector<StickEntry> entries);

  double unitM() const noexcept { return mUnitM; }
  /// Entries (valid ids are 1 .. size()).
  std::uint32_t size() const noexcept { return static_cast<std::uint32_t>(mEntries.size()); }
  const StickEntry& entry(std::uint32_t id) const noexcept { return mEntries[id - 1]; }

  /// Whether any entry is complex (a frame over this table may need secondary rays).
  bool hasSeeThrough() const noexcept { return mSeeThrough; }
  /// The longest entry's length (stick voxels; 0 for an empty table).
  std::uint32_t longestVox() const noexcept { return mLongestVox; }

  /// Level `level`'s colours of stick `id` (1 .. size()), top down, each 2^level units tall. RT-safe.
  /// Alpha is 255 but at level 0 of a complex entry, where a texel below 255 is see-through: a
  /// coarser level's texel is the alpha-weighted mean of those it covers, opaque (a cavity filled
  /// with what surrounds it), so a stick seen far away is the solid it looks like from there.
  std::span<const std::uint32_t> texels(std::uint32_t id, int level) const noexcept {
    const Mips& m = mMips[id - 1];
    const std::size_t k = m.firstLevel + static_cast<std::size_t>(level < m.levels ? level : m.levels - 1);
    return {mTexels.data() + mLevelStart[k], mLevelStart[k + 1] - mLevelStart[k]};
  }

  /// The colour of stick `id` at level `level`, `depthUnits` level-0 units below the voxel's top
  /// (clamped to the stick's colours). RT-safe.
  std::uint32_t colourBelowTop(std::uint32_t id, int level, double depthUnits) const noexcept;

  /// The table as stored in a database (ig_core/README.md, "Database format").
  std::vector<std::byte> serialize() const;
  /// Reads a stored table, validating every count against the block's length. Throws StickTableError.
  static StickTable parse(std::span<const std::byte> block);

 private:
  struct Mips {
    std::uint32_t firstLevel = 0;  // its level 0 in mLevelStart; its levels follow
    int levels = 0;
  };
  double mUnitM;
  bool mSeeThrough = false;
  std::uint32_t mLongestVox = 0;
  std::vector<StickEntry> mEntries;
  std::vector<Mips> mMips;
  std::vector<std::size_t> mLevelStart;  // where each entry's each level starts in mTexels, and one past the last
  std::vector<std::uint32_t> mTexels;    // every entry's mips, level 0 first
};

}  // namespace fieldcast::core
