#pragma once
// Sixteen bilinear samples, RGB or grey, with the frame's bytes staged in registers instead of
// gathered: the AVX-512 kernel's fast path on CPUs with AVX-512 VBMI (byte permutes across whole
// registers). A field's map turns and scales the frame little, so the sixteen samples of a block
// lie within a run of at most twenty RGB frame pixels (sixty-three grey ones) on at most two
// neighbouring frame rows: three 64-byte loads hold every byte they read, and one two-register
// byte permute per channel and neighbour row (upper, lower) lays each lane's left and right
// neighbour side by side for the same 16-bit multiply-add as the gathers'. The same bytes as
// SamplePixel.h's scalar reference.

#include "SamplePixel.h"

#include <cstdint>

namespace fieldcast::warp::sampling {

/// The samples of a staged block.
constexpr int kStagedBlockPx = 16;

/// Samples the whole blocks of 16 of the n pixels at frame coordinates xs, ys into dst (16 ×
/// `channels` bytes a block; channels 3 or 1), one block after another, with samplePixel's bytes,
/// adding their margin violations to `violations`, until a block's neighbours do not fit the
/// staged rows (more than 20 RGB or 63 grey pixels across; more than two rows: a map turned by more
/// than about 4° has some such blocks, by more than about 7.5° only such; or a load past the
/// frame's last byte). Returns the samples done, a multiple of 16: the refused block starts there,
/// nothing of it written; the caller gathers it. One call for a row's run of blocks keeps the
/// constants in registers and the blocks' work overlapping. Call only where
/// fieldcast::simdVbmiEnabled().
int sampleBlocksVbmi(const Source& src, int channels, const float* xs, const float* ys, int n, std::uint8_t* dst,
                     std::uint32_t& violations) noexcept;

/// Whether a run of n samples along a field's row (a straight line in the frame, near enough) is
/// worth offering to sampleBlocksVbmi: its 16-sample blocks rise by at most 1.5 frame rows (a block
/// rising r spans r·15/16 rows: all fit two rows up to r ≈ 1.07, 59 % at 1.5, none past 2.1) and
/// span no more pixels than a block may. A refused
/// block costs its coordinates twice, so in a banked view (the field's map turns the frame by the
/// roll: 10° rises 2.8 rows a block) offering every block made the field slower than gathering it.
/// Short runs (under 32) are left to their blocks; NaN ends say no.
inline bool stagedBlocksLikelyFit(int channels, const float* xs, const float* ys, int n) noexcept {
  if (n < 32) return true;
  const float perBlock = static_cast<float>(kStagedBlockPx) / static_cast<float>(n - 1);
  const float rise = (ys[n - 1] - ys[0]) * perBlock, across = (xs[n - 1] - xs[0]) * perBlock;
  const float widest = channels == 3 ? 19.0f : 62.0f;
  return rise <= 1.5f && rise >= -1.5f && across <= widest && across >= -widest;
}

}  // namespace fieldcast::warp::sampling
