// The UYVY conversion of PixelConversionVbmi.h, in AVX-512 VBMI intrinsics (compiled for it alone
// and called only when the CPU has it).
#include "PixelConversionVbmi.h"

#include "PixelConversion.h"

#include "VbmiTarget.h"

#include <immintrin.h>

#include <array>

namespace fieldcast::warp::conversion {

namespace {

// The gain as a byte table, made again only when the gain changes (the AGC changes it at most once
// a field; a field's rows share it).
struct GainTable {
  std::int32_t gainQ16 = -1;
  alignas(64) std::array<std::uint8_t, 256> bytes{};
};

const GainTable& gainTable(std::int32_t gainQ16) noexcept {
  thread_local GainTable table;
  if (table.gainQ16 != gainQ16) {
    fillGainTable(gainQ16, table.bytes);
    table.gainQ16 = gainQ16;
  }
  return table;
}

// Byte permutes laying pixel k's channels (bytes 3k, 3k + 1, 3k + 2 of the block) into lane k's
// bytes 0 and 2 (bytes 1 and 3 are zeroed by the mask): (R, B), (R, G), (G, G).
constexpr std::array<std::uint8_t, 64> channelPairIndex(int first, int second) {
  std::array<std::uint8_t, 64> index{};
  for (int k = 0; k < 16; ++k) {
    index[static_cast<std::size_t>(4 * k)] = static_cast<std::uint8_t>(3 * k + first);
    index[static_cast<std::size_t>(4 * k + 2)] = static_cast<std::uint8_t>(3 * k + second);
  }
  return index;
}
alignas(64) constexpr std::array<std::uint8_t, 64> kRB = channelPairIndex(0, 2);
alignas(64) constexpr std::array<std::uint8_t, 64> kRG = channelPairIndex(0, 1);
alignas(64) constexpr std::array<std::uint8_t, 64> kGG = channelPairIndex(1, 1);

// Two 16-bit coefficients as one 32-bit lane: `first` multiplies the pair's first channel.
constexpr int pairOf(int first, int second) {
  return static_cast<int>((static_cast<unsigned>(second) << 16) | (static_cast<unsigned>(first) & 0xFFFFu));
}

}  // namespace

FIELDCAST_VBMI int rgbToUyvyBlocksVbmi(const std::uint8_t* in, int widthPx, std::int32_t gainQ16,
                                       std::uint8_t* out) noexcept {
  const bool unity = gainQ16 == kUnityGain;
  __m512i t0 = _mm512_setzero_si512(), t1 = t0, t2 = t0, t3 = t0;
  if (!unity) {
    const GainTable& table = gainTable(gainQ16);
    t0 = _mm512_load_si512(table.bytes.data());
    t1 = _mm512_load_si512(table.bytes.data() + 64);
    t2 = _mm512_load_si512(table.bytes.data() + 128);
    t3 = _mm512_load_si512(table.bytes.data() + 192);
  }
  const __m512i rb = _mm512_load_si512(kRB.data()), rg = _mm512_load_si512(kRG.data()),
                gg = _mm512_load_si512(kGG.data());
  constexpr __mmask64 kBlockBytes = (__mmask64{1} << 48) - 1;
  // toVideoRange's coefficients, as (first, second) pairs for the layouts above
  const __m512i yRB = _mm512_set1_epi32(pairOf(16829, 6416)), yGG = _mm512_set1_epi32(pairOf(16520, 16519));
  // A pair's chroma is linear in its two pixels' channel sums: even lanes take Cb's coefficients,
  // odd lanes Cr's
  constexpr __mmask16 kCbLanes = 0x5555;
  const __m512i cRG = _mm512_mask_blend_epi32(kCbLanes, _mm512_set1_epi32(pairOf(28784, -24103)),
                                              _mm512_set1_epi32(pairOf(-9714, -19070)));
  const __m512i cRB =
      _mm512_mask_blend_epi32(kCbLanes, _mm512_set1_epi32(pairOf(0, -4681)), _mm512_set1_epi32(pairOf(0, 28784)));
  const __m512i yBias = _mm512_set1_epi32((16 << 16) + (1 << 15));       // the offset and the rounding
  const __m512i cBias = _mm512_set1_epi32((2 * 128 << 16) + (1 << 16));  // both pixels' offsets and the rounding
  int x = 0;
  for (; x + 16 <= widthPx; x += 16) {
    __m512i rgb = _mm512_maskz_loadu_epi8(kBlockBytes, in + 3 * x);
    if (!unity) {
      // Byte i's gained value: entry i & 127 of the lower or upper half by its bit 7
      const __m512i low = _mm512_permutex2var_epi8(t0, rgb, t1), high = _mm512_permutex2var_epi8(t2, rgb, t3);
      rgb = _mm512_mask_blend_epi8(_mm512_movepi8_mask(rgb), low, high);
    }
    const __m512i pRB = _mm512_maskz_permutexvar_epi8(kBytes0And2, rb, rgb);
    const __m512i pRG = _mm512_maskz_permutexvar_epi8(kBytes0And2, rg, rgb);
    const __m512i pGG = _mm512_maskz_permutexvar_epi8(kBytes0And2, gg, rgb);
    const __m512i y =
        _mm512_add_epi32(_mm512_add_epi32(_mm512_madd_epi16(pRB, yRB), _mm512_madd_epi16(pGG, yGG)), yBias);
    // Each pair's channel sums in both its lanes (_MM_PERM_CDAB swaps the lanes of each pair; a
    // 16-bit half's sum, at most 510, stays in its half)
    const __m512i sRG = _mm512_add_epi32(pRG, _mm512_shuffle_epi32(pRG, _MM_PERM_CDAB));
    const __m512i sRB = _mm512_add_epi32(pRB, _mm512_shuffle_epi32(pRB, _MM_PERM_CDAB));
    const __m512i chroma =
        _mm512_add_epi32(_mm512_add_epi32(_mm512_madd_epi16(sRG, cRG), _mm512_madd_epi16(sRB, cRB)), cBias);
    const __m512i c = _mm512_srli_epi32(chroma, 17);
    const __m512i luma = _mm512_srli_epi32(y, 16);
    // Little-endian 16-bit [C, Y]: byte 2x is the chroma, 2x + 1 the luma
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 2 * x),
                        _mm512_cvtepi32_epi16(_mm512_or_si512(c, _mm512_slli_epi32(luma, 8))));
  }
  return x;
}

}  // namespace fieldcast::warp::conversion
