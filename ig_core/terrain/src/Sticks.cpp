// The shared stick table: validation, mips, and its stored form.
#include <ig_core/Sticks.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace fieldcast::core {
namespace {

static_assert(std::endian::native == std::endian::little, "the stored table is little-endian; add byte swaps");

constexpr std::size_t kHeaderBytes = 16;  // entry count, reserved, unit
constexpr std::size_t kEntryBytes = 8;    // kind, 3 reserved, length

std::size_t texelCount(StickKind kind, std::uint32_t lengthVox) noexcept {
  return kind == StickKind::Uniform ? 1 : lengthVox;
}

bool validKind(StickKind kind) noexcept {
  return kind == StickKind::Uniform || kind == StickKind::Textured || kind == StickKind::Complex;
}

// The mean colour of `texels`, channel by channel (rounded), opaque.
std::uint32_t meanRgb(std::span<const std::uint32_t> texels) noexcept {
  std::uint32_t out = kOpaqueRgba;
  const auto n = static_cast<std::uint32_t>(texels.size());
  for (int shift = 0; shift < 24; shift += 8) {
    std::uint32_t sum = 0;
    for (const std::uint32_t t : texels) sum += (t >> shift) & 0xFFu;
    out |= ((sum + n / 2) / n) << shift;
  }
  return out;
}

// A complex stick's coarse texel over `covered`: the alpha-weighted mean colour, opaque. All of
// them cavities: what the ray would meet below them, else above (`run`: the entry's level-0
// texels, `first`: where `covered` starts in it) — a cavity is filled with its surroundings.
std::uint32_t filledRgb(std::span<const std::uint32_t> run, std::size_t first, std::size_t count) noexcept {
  std::uint64_t sum[3] = {0, 0, 0}, weight = 0;
  for (std::size_t k = first; k < first + count; ++k) {
    const std::uint32_t a = run[k] >> 24;
    for (int c = 0; c < 3; ++c) sum[c] += a * ((run[k] >> (8 * c)) & 0xFFu);
    weight += a;
  }
  if (weight == 0) {
    for (std::size_t k = first + count; k < run.size(); ++k)
      if ((run[k] >> 24) != 0) return run[k] | kOpaqueRgba;
    for (std::size_t k = first; k-- > 0;)
      if ((run[k] >> 24) != 0) return run[k] | kOpaqueRgba;
    return kOpaqueRgba;  // nothing to see at all: black
  }
  std::uint32_t out = kOpaqueRgba;
  for (int c = 0; c < 3; ++c) out |= static_cast<std::uint32_t>((sum[c] + weight / 2) / weight) << (8 * c);
  return out;
}

template <typename T>
T load(std::span<const std::byte> bytes, std::size_t offset) noexcept {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

}  // namespace

StickTable::StickTable(double unitM, std::vector<StickEntry> entries) : mUnitM(unitM), mEntries(std::move(entries)) {
  if (!(unitM >= 1e-3 && unitM <= 1000.0)) {
    throw StickTableError("stick table: unit of " + std::to_string(unitM) + " m (expected 0.001 .. 1000 m)");
  }
  if (mEntries.size() > kMaxStickEntries) {
    throw StickTableError("stick table: " + std::to_string(mEntries.size()) + " entries (at most " +
                          std::to_string(kMaxStickEntries) + ")");
  }
  mMips.resize(mEntries.size());
  for (std::size_t e = 0; e < mEntries.size(); ++e) {
    const StickEntry& entry = mEntries[e];
    const std::string which = "stick table entry " + std::to_string(e + 1);
    if (!validKind(entry.kind)) {
      throw StickTableError(which + ": unknown kind " + std::to_string(static_cast<int>(entry.kind)));
    }
    if (entry.lengthVox < 1 || entry.lengthVox > kMaxStickLength) {
      throw StickTableError(which + ": length " + std::to_string(entry.lengthVox) + " (1 .. " +
                            std::to_string(kMaxStickLength) + " stick voxels)");
    }
    if (entry.texels.size() != texelCount(entry.kind, entry.lengthVox)) {
      throw StickTableError(which + ": " + std::to_string(entry.texels.size()) + " colours for a " +
                            (entry.kind == StickKind::Uniform
                                 ? "uniform stick (1 expected)"
                                 : (entry.kind == StickKind::Textured ? "textured" : "complex") +
                                       std::string(" stick of ") + std::to_string(entry.lengthVox)));
    }
    // Mip L: ceil(n / 2^L) colours, each the mean of the level-0 colours it covers; down to one.
    // Only a complex entry's level 0 keeps its alpha; it has a level 1 even when one texel long.
    const bool complex = entry.kind == StickKind::Complex;
    mSeeThrough = mSeeThrough || complex;
    mLongestVox = std::max(mLongestVox, entry.lengthVox);
    Mips& m = mMips[e];
    m.firstLevel = static_cast<std::uint32_t>(mLevelStart.size());
    const std::span<const std::uint32_t> run(entry.texels);
    const std::size_t n = run.size();
    for (int level = 0;; ++level) {
      const std::size_t span = std::size_t{1} << level;
      const std::size_t count = (n + span - 1) / span;
      mLevelStart.push_back(mTexels.size());
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t first = k * span;
        const std::size_t covered = std::min(span, n - first);
        if (complex && level == 0) {
          // A cavity keeps alpha 0 but takes the colour it is filled with at coarser levels, so a
          // path that cannot see through it (a secondary ray's second object) shows that.
          mTexels.push_back((run[k] >> 24) != 0 ? run[k] : filledRgb(run, k, 1) & 0x00FFFFFFu);
        } else if (complex) {
          mTexels.push_back(filledRgb(run, first, covered));
        } else {
          mTexels.push_back(meanRgb(run.subspan(first, covered)));
        }
      }
      m.levels = level + 1;
      if (count == 1 && !(complex && level == 0)) break;
    }
  }
  mLevelStart.push_back(mTexels.size());  // one past the last level
}

std::uint32_t StickTable::colourBelowTop(std::uint32_t id, int level, double depthUnits) const noexcept {
  const std::span<const std::uint32_t> colours = texels(id, level);
  const double x = std::ldexp(depthUnits, -level);
  const double k = x > 0.0 ? std::floor(x) : 0.0;  // above the top, or NaN: the top
  const double last = static_cast<double>(colours.size() - 1);
  return colours[static_cast<std::size_t>(k < last ? k : last)];
}

std::vector<std::byte> StickTable::serialize() const {
  // Every field is a whole number of 32-bit words: built as words, handed out as bytes
  std::vector<std::uint32_t> words{size(), 0u, 0u, 0u};
  std::memcpy(&words[2], &mUnitM, sizeof mUnitM);
  for (const StickEntry& e : mEntries) {
    words.push_back(static_cast<std::uint32_t>(e.kind));  // kind in the first byte, three reserved
    words.push_back(e.lengthVox);
  }
  for (const StickEntry& e : mEntries) words.insert(words.end(), e.texels.begin(), e.texels.end());
  const std::span<const std::byte> bytes = std::as_bytes(std::span(words));
  return {bytes.begin(), bytes.end()};
}

StickTable StickTable::parse(std::span<const std::byte> block) {
  if (block.size() < kHeaderBytes) {
    throw StickTableError("stick table of " + std::to_string(block.size()) + " bytes (its header needs 16)");
  }
  const auto count = load<std::uint32_t>(block, 0);
  if (count > kMaxStickEntries || kEntryBytes * count > block.size() - kHeaderBytes) {
    throw StickTableError("stick table: " + std::to_string(count) + " entries do not fit in its " +
                          std::to_string(block.size()) + " bytes");
  }
  std::vector<StickEntry> entries(count);
  std::size_t texels = 0;
  for (std::uint32_t e = 0; e < count; ++e) {
    const std::size_t at = kHeaderBytes + kEntryBytes * e;
    entries[e].kind = static_cast<StickKind>(load<std::uint8_t>(block, at));
    entries[e].lengthVox = load<std::uint32_t>(block, at + 4);
    if (!validKind(entries[e].kind)) {
      throw StickTableError("stick table entry " + std::to_string(e + 1) + ": unknown kind " +
                            std::to_string(load<std::uint8_t>(block, at)));
    }
    if (entries[e].lengthVox < 1 || entries[e].lengthVox > kMaxStickLength) {
      throw StickTableError("stick table entry " + std::to_string(e + 1) + ": length " +
                            std::to_string(entries[e].lengthVox));
    }
    texels += texelCount(entries[e].kind, entries[e].lengthVox);
  }
  const std::size_t texelStart = kHeaderBytes + kEntryBytes * count;
  if (block.size() - texelStart != 4 * texels) {
    throw StickTableError("stick table: " + std::to_string(block.size() - texelStart) + " bytes of colours, its " +
                          std::to_string(count) + " entries need " + std::to_string(4 * texels));
  }
  std::size_t at = texelStart;
  for (StickEntry& e : entries) {
    e.texels.resize(texelCount(e.kind, e.lengthVox));
    std::memcpy(e.texels.data(), block.data() + at, 4 * e.texels.size());
    at += 4 * e.texels.size();
  }
  return StickTable(load<double>(block, 8), std::move(entries));
}

}  // namespace fieldcast::core
