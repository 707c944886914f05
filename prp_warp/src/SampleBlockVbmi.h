#pragma once
// Sixteen bilinear samples, RGB or grey, with the frame's bytes staged in registers instead of
// gathered: the AVX-512 kernel's fast path on CPUs with AVX-512 VBMI (a byte permute across a
// whole register). A field's map turns and scales the frame little, so the sixteen samples of a
// block lie within a run of at most twenty RGB frame pixels (sixty-three grey ones) on at most two
// neighbouring frame rows: three 64-byte loads hold every byte they read, and one byte permute per
// channel and row lays each lane's left and right neighbour side by side for the same 16-bit
// multiply-add as the gathers'. The same bytes as SamplePixel.h's scalar reference.

#include "SamplePixel.h"

#include <cstdint>

namespace fieldcast::warp::sampling {

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

}  // namespace fieldcast::warp::sampling
