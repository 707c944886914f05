// The staged sampling of SampleBlockVbmi.h, in AVX-512 VBMI intrinsics (compiled for it alone and
// called only when the CPU has it).
#include "SampleBlockVbmi.h"

#include "VbmiTarget.h"

#include <immintrin.h>

#include <array>
#include <cstddef>

namespace fieldcast::warp::sampling {

namespace {

// SamplePixel.h's coordinates in 16 lanes: x0, y0 (the upper-left neighbour), fx, fy (1/256 px),
// and the lanes inside the frame (the violations are the others).
struct BlockCoordinates {
  __m512i x0, y0, fx, fy;
  __mmask16 inside;
};

FIELDCAST_VBMI inline BlockCoordinates coordinatesOf(const Source& src, const float* xs, const float* ys) noexcept {
  const __m512 px = _mm512_loadu_ps(xs), py = _mm512_loadu_ps(ys);
  const __m512 zero = _mm512_setzero_ps(), half = _mm512_set1_ps(0.5f), unit = _mm512_set1_ps(static_cast<float>(kOne));
  const __m512 w = _mm512_set1_ps(static_cast<float>(src.widthPx)),
               h = _mm512_set1_ps(static_cast<float>(src.heightPx));
  BlockCoordinates b;
  // Every lane between the frame's outer pixel centres (false for NaN): no lane violates the margins
  // and the clamps change nothing but a lane on the last centre, whose x0 (y0) is then W − 1
  // (H − 1) with weight 0 on its right (lower) neighbour instead of W − 2 with weight 256 on it —
  // the same bytes. Such a lane's neighbour past the frame is in the staged rows or the block is
  // refused (the checks below). Skipping the clamps shortens the chain to the block's loads.
  const __mmask16 betweenCentres =
      _mm512_cmp_ps_mask(px, half, _CMP_GE_OQ) & _mm512_cmp_ps_mask(px, _mm512_sub_ps(w, half), _CMP_LE_OQ) &
      _mm512_cmp_ps_mask(py, half, _CMP_GE_OQ) & _mm512_cmp_ps_mask(py, _mm512_sub_ps(h, half), _CMP_LE_OQ);
  if (betweenCentres == 0xFFFF) {
    const __m512i ix = _mm512_cvttps_epi32(_mm512_add_ps(_mm512_mul_ps(_mm512_sub_ps(px, half), unit), half));
    const __m512i iy = _mm512_cvttps_epi32(_mm512_add_ps(_mm512_mul_ps(_mm512_sub_ps(py, half), unit), half));
    const __m512i fraction = _mm512_set1_epi32(kOne - 1);
    b.inside = 0xFFFF;
    b.x0 = _mm512_srai_epi32(ix, kFracBits);
    b.y0 = _mm512_srai_epi32(iy, kFracBits);
    b.fx = _mm512_and_si512(ix, fraction);
    b.fy = _mm512_and_si512(iy, fraction);
    return b;
  }
  b.inside = _mm512_cmp_ps_mask(px, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(px, w, _CMP_LE_OQ) &
             _mm512_cmp_ps_mask(py, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(py, h, _CMP_LE_OQ);
  // Pixel-centre origin; a false compare (NaN) gives 0, as in the scalar form
  __m512 qx = _mm512_sub_ps(px, half), qy = _mm512_sub_ps(py, half);
  qx = _mm512_min_ps(_mm512_maskz_mov_ps(_mm512_cmp_ps_mask(qx, zero, _CMP_GE_OQ), qx),
                     _mm512_set1_ps(static_cast<float>(src.widthPx - 1)));
  qy = _mm512_min_ps(_mm512_maskz_mov_ps(_mm512_cmp_ps_mask(qy, zero, _CMP_GE_OQ), qy),
                     _mm512_set1_ps(static_cast<float>(src.heightPx - 1)));
  const __m512i ix = _mm512_cvttps_epi32(_mm512_add_ps(_mm512_mul_ps(qx, unit), half));
  const __m512i iy = _mm512_cvttps_epi32(_mm512_add_ps(_mm512_mul_ps(qy, unit), half));
  b.x0 = _mm512_min_epi32(_mm512_srai_epi32(ix, kFracBits), _mm512_set1_epi32(src.widthPx - 2));
  b.y0 = _mm512_min_epi32(_mm512_srai_epi32(iy, kFracBits), _mm512_set1_epi32(src.heightPx - 2));
  b.fx = _mm512_sub_epi32(ix, _mm512_slli_epi32(b.x0, kFracBits));
  b.fy = _mm512_sub_epi32(iy, _mm512_slli_epi32(b.y0, kFracBits));
  return b;
}

// Byte permutes packing byte 2 of each lane of three channel registers as r g b r g b …: red and
// green from the first pair of registers (bit 6 picks the second), then blue put in.
constexpr std::array<std::uint8_t, 64> packIndex(bool blue) {
  std::array<std::uint8_t, 64> index{};
  for (int k = 0; k < 16; ++k) {
    const auto at = static_cast<std::size_t>(3 * k);
    index[at] = static_cast<std::uint8_t>(blue ? at : 4 * k + 2);
    index[at + 1] = static_cast<std::uint8_t>(blue ? at + 1 : 64 + 4 * k + 2);
    index[at + 2] = static_cast<std::uint8_t>(blue ? 64 + 4 * k + 2 : 0);
  }
  return index;
}
alignas(64) constexpr std::array<std::uint8_t, 64> kRedGreen = packIndex(false);
alignas(64) constexpr std::array<std::uint8_t, 64> kAndBlue = packIndex(true);

// Channel c of each lane's upper and lower neighbour pairs, (left, right) as 16-bit halves, blended
// along x and then y (upper · (256 − fy) + lower · fy) and stored: 16 × C bytes.
template <int C>
FIELDCAST_VBMI inline void blendAndStore(const __m512i (&upperPairs)[C], const __m512i (&lowerPairs)[C], __m512i fx,
                                         __m512i fy, std::uint8_t* dst) noexcept {
  const __m512i weightsX = _mm512_or_si512(_mm512_sub_epi32(_mm512_set1_epi32(kOne), fx), _mm512_slli_epi32(fx, 16));
  const __m512i round = _mm512_set1_epi32(1 << (2 * kFracBits - 1));
  __m512i rounded[C];  // channel c of lane k: (sample + ½) · 2^16, the sample in byte 2
  for (int c = 0; c < C; ++c) {
    const __m512i upper = _mm512_madd_epi16(upperPairs[c], weightsX);
    const __m512i lower = _mm512_madd_epi16(lowerPairs[c], weightsX);
    const __m512i value =
        _mm512_add_epi32(_mm512_slli_epi32(upper, kFracBits), _mm512_mullo_epi32(_mm512_sub_epi32(lower, upper), fy));
    rounded[c] = _mm512_add_epi32(value, round);
  }
  if constexpr (C == 1) {
    // Each lane's byte 2: 16 bytes
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst), _mm512_cvtepi32_epi8(_mm512_srli_epi32(rounded[0], 16)));
  } else {
    // Byte 2 of each lane of the three channels → 48 bytes r g b r g b …: red and green by one
    // two-register permute, blue put in by another
    _mm512_mask_storeu_epi8(
        dst, (__mmask64{1} << 48) - 1,
        _mm512_permutex2var_epi8(_mm512_permutex2var_epi8(rounded[0], _mm512_load_si512(kRedGreen.data()), rounded[1]),
                                 _mm512_load_si512(kAndBlue.data()), rounded[2]));
  }
}

// The staged block of C channels (3: RGB, 1: grey); false, having written nothing, when its
// neighbours do not fit the staged rows.
template <int C>
FIELDCAST_VBMI inline bool stagedBlock(const Source& src, const BlockCoordinates& b, std::uint8_t* dst) noexcept {
  // x0 − xmin at most this: the right neighbour's last byte is then byte 62 (RGB) or 63 (grey)
  constexpr int kMaxSpanPx = C == 3 ? 19 : 62;
  // The block's first neighbour: a field's map runs one way along a row, so the least x0 and y0
  // are those of its first or its last lane (checked below: every lane must lie within the span)
  const int x0First = _mm_cvtsi128_si32(_mm512_castsi512_si128(b.x0));
  const int y0First = _mm_cvtsi128_si32(_mm512_castsi512_si128(b.y0));
  const int x0Last = _mm_extract_epi32(_mm512_extracti32x4_epi32(b.x0, 3), 3);
  const int y0Last = _mm_extract_epi32(_mm512_extracti32x4_epi32(b.y0, 3), 3);
  const int xmin = x0First < x0Last ? x0First : x0Last, ymin = y0First < y0Last ? y0First : y0Last;
  const int rise = (y0First < y0Last ? y0Last : y0First) - ymin;  // upper rows climbed, end to end
  if (rise > kMaxStagedRiseRows) return false;
  const bool turned = rise > 1;
  const __m512i dx = _mm512_sub_epi32(b.x0, _mm512_set1_epi32(xmin));
  const __m512i dy = _mm512_sub_epi32(b.y0, _mm512_set1_epi32(ymin));
  // Unsigned: a lane before the first (negative) fails too. A level block's middle lanes may lie a
  // row below its ends (where a row of the map turns back): still two rows.
  if ((_mm512_cmpgt_epu32_mask(dx, _mm512_set1_epi32(kMaxSpanPx)) |
       _mm512_cmpgt_epu32_mask(dy, _mm512_set1_epi32(turned ? rise : 1))) != 0)
    return false;
  const __mmask16 onSecondRow = _mm512_test_epi32_mask(dy, dy);      // lanes whose upper row is not the first
  const int lastRow = turned ? rise + 1 : onSecondRow != 0 ? 2 : 1;  // rows 0 … lastRow are read
  const std::int64_t stride = src.strideBytes;
  const std::int64_t first = static_cast<std::int64_t>(ymin) * stride + std::int64_t{xmin} * C;
  const std::int64_t end = static_cast<std::int64_t>(src.heightPx - 1) * stride + std::int64_t{src.widthPx} * C;
  if (first + lastRow * stride + 64 > end) return false;
  const std::uint8_t* p = src.base + first;

  // Lane k's bytes 0 and 2 index its left and right neighbour's channel in a pair of staged rows
  // (bit 6 picks the second); the two-register byte permute leaves bytes 1 and 3 zero (or they are
  // cleared), so each is a 16-bit (left, right) pair for the multiply-add with the weights
  // (256 − fx, fx).
  const __m512i left = C == 3 ? _mm512_add_epi32(dx, _mm512_slli_epi32(dx, 1)) : dx;  // C · (x0 − xmin)
  const __m512i pairs = _mm512_or_si512(left, _mm512_slli_epi32(_mm512_add_epi32(left, _mm512_set1_epi32(C)), 16));
  const __m512i second = _mm512_set1_epi32(0x00400040);  // bit 6 of bytes 0 and 2
  __m512i upperPairs[C], lowerPairs[C];
  if (!turned) {
    // Two or three rows: upper rows from rows 0 and 1, lower rows from rows 1 and 2 (bit 6 set
    // where the lane's upper row is row 1)
    const __m512i row0 = _mm512_loadu_si512(p), row1 = _mm512_loadu_si512(p + stride);
    const __m512i row2 = lastRow == 2 ? _mm512_loadu_si512(p + 2 * stride) : row1;
    const __m512i pairIndex = _mm512_mask_add_epi32(pairs, onSecondRow, pairs, second);
    for (int c = 0; c < C; ++c) {
      const __m512i index = _mm512_add_epi32(pairIndex, _mm512_set1_epi32(c * 0x10001));
      upperPairs[c] = _mm512_maskz_permutex2var_epi8(kBytes0And2, row0, index, row1);
      lowerPairs[c] = _mm512_maskz_permutex2var_epi8(kBytes0And2, row1, index, row2);
    }
  } else {
    // A turned block: rows 0 … rise + 1, staged two at a time. Rows 2j and 2j + 1 hold the upper
    // rows of the lanes whose dy is 2j or 2j + 1 and the lower rows of those whose dy + 1 is. One
    // permute of the two serves both: a lane's upper pair in its bytes 0 and 2, its lower pair in
    // bytes 1 and 3.
    const __m512i one = _mm512_set1_epi32(1);
    const __m512i below = _mm512_add_epi32(dy, one);
    const __m512i upperIndex = _mm512_mask_add_epi32(pairs, _mm512_test_epi32_mask(dy, one), pairs, second);
    const __m512i lowerIndex = _mm512_mask_add_epi32(pairs, _mm512_test_epi32_mask(below, one), pairs, second);
    const __m512i index = _mm512_or_si512(upperIndex, _mm512_slli_epi32(lowerIndex, 8));
    // Each index byte's pair of rows (dy / 2 for bytes 0 and 2, (dy + 1) / 2 for bytes 1 and 3)
    const __m512i pairOfLane =
        _mm512_or_si512(_mm512_srli_epi32(dy, 1), _mm512_slli_epi32(_mm512_srli_epi32(below, 1), 8));
    const __m512i pairOfByte = _mm512_or_si512(pairOfLane, _mm512_slli_epi32(pairOfLane, 16));
    // Each byte starts as its index and is overwritten (vpermi2b, merge-masked) by the permute of
    // its own pair of rows: every byte has one, so none is left an index
    __m512i both[C];
    for (int c = 0; c < C; ++c) both[c] = _mm512_add_epi32(index, _mm512_set1_epi32(c * 0x01010101));
    for (int j = 0; 2 * j <= lastRow; ++j) {
      const __m512i rowA = _mm512_loadu_si512(p + 2 * j * stride);
      const __m512i rowB = 2 * j + 1 <= lastRow ? _mm512_loadu_si512(p + (2 * j + 1) * stride) : rowA;
      const __mmask64 here = _mm512_cmpeq_epi8_mask(pairOfByte, _mm512_set1_epi8(static_cast<char>(j)));
      for (int c = 0; c < C; ++c) both[c] = _mm512_mask2_permutex2var_epi8(rowA, both[c], here, rowB);
    }
    const __m512i bytes0And2 = _mm512_set1_epi32(0x00FF00FF);
    for (int c = 0; c < C; ++c) {
      upperPairs[c] = _mm512_and_si512(both[c], bytes0And2);
      lowerPairs[c] = _mm512_and_si512(_mm512_srli_epi32(both[c], 8), bytes0And2);
    }
  }
  blendAndStore<C>(upperPairs, lowerPairs, b.fx, b.fy, dst);
  return true;
}

template <int C>
FIELDCAST_VBMI int sampleBlocks(const Source& source, const float* xs, const float* ys, int n, std::uint8_t* dst,
                                std::uint32_t& violations) noexcept {
  // Locals: the stores of samples (bytes) may alias anything, so a count or the frame's sizes
  // read through a reference would be read again, and its constants remade, every block
  const Source src = source;
  std::uint32_t outside = 0;
  int i = 0;
  for (; i + kStagedBlockPx <= n; i += kStagedBlockPx) {
    const BlockCoordinates b = coordinatesOf(src, xs + i, ys + i);
    if (!stagedBlock<C>(src, b, dst + C * i)) break;
    outside += kStagedBlockPx - static_cast<std::uint32_t>(__builtin_popcount(b.inside));
  }
  violations += outside;
  return i;
}

}  // namespace

FIELDCAST_VBMI int sampleBlocksVbmi(const Source& src, int channels, const float* xs, const float* ys, int n,
                                    std::uint8_t* dst, std::uint32_t& violations) noexcept {
  return channels == 3 ? sampleBlocks<3>(src, xs, ys, n, dst, violations)
                       : sampleBlocks<1>(src, xs, ys, n, dst, violations);
}

}  // namespace fieldcast::warp::sampling
