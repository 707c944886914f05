#pragma once
// Sixteen bilinear samples, RGB or grey, with the frame's bytes staged in registers instead of
// gathered: the AVX-512 kernel's fast path on CPUs with AVX-512 VBMI (byte permutes across whole
// registers). A field's map scales the frame little, so the sixteen samples of a block lie within
// a run of at most twenty RGB frame pixels (sixty-three grey ones) across. Level, they lie on at
// most two neighbouring frame rows: three 64-byte loads hold every byte they read, and one
// two-register byte permute per channel and neighbour row (upper, lower) lays each lane's left and
// right neighbour side by side for the same 16-bit multiply-add as the gathers'. Turned by a
// banked view's roll, they climb up to sixteen rows: the rows are loaded two at a time and one
// permute of each two serves the lanes whose upper or lower neighbours lie on them. The same bytes
// as SamplePixel.h's scalar reference.

#include "SamplePixel.h"

#include <cstdint>

namespace fieldcast::warp::sampling {

/// The samples of a staged block.
constexpr int kStagedBlockPx = 16;

/// The most frame rows a staged block's upper neighbours may climb, first lane to last: a field's
/// row turned 90° climbs 15 (scale 1); the block's loads are its climb + 2 rows.
constexpr int kMaxStagedRiseRows = 16;

/// Samples the whole blocks of 16 of the n pixels at frame coordinates xs, ys into dst (16 ×
/// `channels` bytes a block; channels 3 or 1), one block after another, with samplePixel's bytes,
/// adding their margin violations to `violations`, until a block's neighbours do not fit the
/// staged rows (more than 20 RGB or 63 grey pixels across, as in a field zoomed out by more than
/// about 1.25; a climb of more than kMaxStagedRiseRows rows; or a load past the frame's last byte).
/// Returns the samples done, a multiple of 16: the refused block starts there, nothing of it
/// written; the caller gathers it. One call for a row's run of blocks keeps the constants in
/// registers and the blocks' work overlapping. Call only where fieldcast::simdVbmiEnabled().
int sampleBlocksVbmi(const Source& src, int channels, const float* xs, const float* ys, int n, std::uint8_t* dst,
                     std::uint32_t& violations) noexcept;

/// Whether a run of n samples along a field's row (a straight line in the frame, near enough) is
/// worth offering to sampleBlocksVbmi: its 16-sample blocks span no more pixels across than a block
/// may and climb no more rows (a run climbing r rows per 16 samples climbs r·15/16 from a block's
/// first lane to its last, so its upper rows lie at most ⌈r·15/16⌉ ≤ 15 apart for r ≤ 16). A
/// refused block costs its coordinates twice, so a run whose blocks would mostly be refused is
/// gathered straight away. Short runs (under 32) are left to their blocks; NaN ends say no.
inline bool stagedBlocksLikelyFit(int channels, const float* xs, const float* ys, int n) noexcept {
  if (n < 32) return true;
  const float perBlock = static_cast<float>(kStagedBlockPx) / static_cast<float>(n - 1);
  const float rise = (ys[n - 1] - ys[0]) * perBlock, across = (xs[n - 1] - xs[0]) * perBlock;
  const float widest = channels == 3 ? 19.0f : 62.0f;
  const auto most = static_cast<float>(kMaxStagedRiseRows);
  return rise <= most && rise >= -most && across <= widest && across >= -widest;
}

}  // namespace fieldcast::warp::sampling
