#pragma once
// R'G'B' → UYVY 4:2:2 with gain, sixteen pixels at a time, in AVX-512 VBMI: the conversion's fast
// path on CPUs that have it (level avx512vbmi). The gain is one byte lookup (two 128-entry byte
// permutes); three byte permutes lay each pixel's channels out as the 16-bit pairs (R, B), (R, G)
// and (G, G), so Y takes two 16-bit multiply-adds (the coefficient of G, 33039, does not fit 16 bits:
// G · 16520 + G · 16519), and a pair's Cb or Cr two more on the pair's channel sums, where the
// lanes' form takes nine 32-bit multiplies. The same bytes as PixelConversion.h's scalar reference.

#include <cstdint>

namespace fieldcast::warp::conversion {

/// Converts the whole blocks of 16 of the row's `widthPx` pixels of packed R'G'B' (`in`) under
/// `gainQ16` (within [0, kMaxGain]) into UYVY (`out`, 32 bytes a block), as toUyvyRowScalar does;
/// returns the pixels done, a multiple of 16 (the caller converts the rest). Reads no byte past
/// the row. Call only where fieldcast::simdVbmiEnabled().
int rgbToUyvyBlocksVbmi(const std::uint8_t* in, int widthPx, std::int32_t gainQ16, std::uint8_t* out) noexcept;

}  // namespace fieldcast::warp::conversion
