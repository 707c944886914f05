// Bilinear resampling kernels. The reference evaluates the map per pixel in double precision;
// the fast path splits each row into three short loops a compiler vectorises: generate the
// frame coordinates (forward differences for the quadratic), convert them to 8-bit fixed point
// while counting margin violations, then gather and blend in integers (SSE2 for RGB: one pixel's
// four neighbours blended in 16-bit lanes, the layout OpenCV's remap also uses).
#include <prp_warp/Resample.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// The branch-free loops are built twice, for AVX2 and for baseline x86-64, and chosen at load
// time: the service runs on whatever CPU the rig has (FIELDCAST_NATIVE is off by default). Not
// under ThreadSanitizer: the loader runs the clones' ifunc resolver before TSan's runtime is up,
// and the instrumented resolver crashes the program at start.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__) && \
    !defined(__SANITIZE_THREAD__)
#define FIELDCAST_WARP_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FIELDCAST_WARP_CLONES
#endif

namespace fieldcast::warp {
namespace {

constexpr int kFracBits = 8;  // 1/256 px: ≤ ½ grey level of position error at 255 levels/px
constexpr int kOne = 1 << kFracBits;
constexpr int kLanes = 4;

int channelsOf(PixelFormat f) noexcept { return f == PixelFormat::Rgb8 ? 3 : 1; }

/// Frame x coordinates of pixel centres firstPx + i + ½ of one raster row under a quadratic, stepped by
/// forward differences: lane j holds pixels j, j+4, j+8, …; each lane advances by its first
/// difference, which advances by the constant second difference.
void quadraticRow(const std::array<double, 6>& c, int firstPx, double v, int n, float* out) noexcept {
  // Along the row the map is a parabola in u: A + B·u + C·u².
  const double a = c[0] + c[2] * v + c[5] * v * v;
  const double b = c[1] + c[3] * v;
  const double cc = c[4];
  auto at = [&](int i) noexcept {
    const double u = firstPx + i + 0.5;
    return a + b * u + cc * u * u;
  };
  // Four lanes as one vector (GCC/Clang vector extension: one SSE register). Single precision
  // is enough because every strip restarts from the exact double values: over a strip of 128
  // pixels the accumulated error stays below 1e-3 px.
  typedef float Lanes __attribute__((vector_size(kLanes * sizeof(float))));
  auto f = [](double x) noexcept { return static_cast<float>(x); };
  Lanes value = {f(at(0)), f(at(1)), f(at(2)), f(at(3))};
  Lanes step = {f(at(4) - at(0)), f(at(5) - at(1)), f(at(6) - at(2)), f(at(7) - at(3))};
  const float ss = f(at(2 * kLanes) - 2.0 * at(kLanes) + at(0));
  const Lanes stepStep = {ss, ss, ss, ss};
  for (int i = 0; i < n; i += kLanes) {
    // Emit four pixels, then climb every lane to its next pixel
    std::memcpy(out + i, &value, sizeof value);
    value += step;
    step += stepStep;
  }
}

/// Converts one row of frame coordinates into what the gather needs — the byte offset of the
/// top-left neighbour and the weight pairs (1 − f, f) in 1/256 for x and y — clamping to
/// the frame and counting the coordinates outside it (NaN included). Branch-free, so the
/// compiler vectorises it.
FIELDCAST_WARP_CLONES
std::uint32_t toSampleOffsets(const float* x, const float* y, int n, const Image& src, std::int32_t* offset,
                              std::uint32_t* weightsX, std::uint32_t* weightsY) noexcept {
  const int w = src.widthPx(), h = src.heightPx();
  const int channels = channelsOf(src.format());
  const auto stride = static_cast<std::int32_t>(src.strideBytes());
  const float maxX = static_cast<float>(w - 1), maxY = static_cast<float>(h - 1);
  const float fw = static_cast<float>(w), fh = static_cast<float>(h);
  const int lastX = w - 2, lastY = h - 2;
  std::uint32_t violations = 0;
  for (int i = 0; i < n; ++i) {
    const float px = x[i], py = y[i];
    // Bitwise, not logical, and: no branches in the loop
    const unsigned inside = static_cast<unsigned>(px >= 0.0f) & static_cast<unsigned>(px <= fw) &
                            static_cast<unsigned>(py >= 0.0f) & static_cast<unsigned>(py <= fh);
    violations += 1u - inside;
    // Pixel-centre origin, clamped; written so that NaN clamps to 0 (comparisons with NaN are false)
    float qx = px - 0.5f, qy = py - 0.5f;
    qx = qx >= 0.0f ? qx : 0.0f;
    qy = qy >= 0.0f ? qy : 0.0f;
    qx = qx <= maxX ? qx : maxX;
    qy = qy <= maxY ? qy : maxY;
    const auto ix = static_cast<std::int32_t>(qx * kOne + 0.5f);
    const auto iy = static_cast<std::int32_t>(qy * kOne + 0.5f);
    // The last column/row samples its left/upper neighbour with weight 0
    const std::int32_t x0 = std::min(ix >> kFracBits, lastX);
    const std::int32_t y0 = std::min(iy >> kFracBits, lastY);
    const std::int32_t fx = ix - (x0 << kFracBits);
    const std::int32_t fy = iy - (y0 << kFracBits);
    offset[i] = y0 * stride + x0 * channels;
    // (1 − f, f) as two 16-bit halves: the operand of a 16-bit multiply-add
    weightsX[i] = static_cast<std::uint32_t>(kOne - fx) | (static_cast<std::uint32_t>(fx) << 16);
    weightsY[i] = static_cast<std::uint32_t>(kOne - fy) | (static_cast<std::uint32_t>(fy) << 16);
  }
  return violations;
}

/// Fixed-point bilinear gather of one row from precomputed offsets and weights. The portable
/// version: any channel count, 32-bit integer blend.
template <int C>
void gatherRowScalar(const Image& src, const std::int32_t* offset, const std::uint32_t* weightsX,
                     const std::uint32_t* weightsY, int n, std::uint8_t* dst) noexcept {
  const std::uint8_t* base = src.row(0);
  const auto stride = static_cast<std::ptrdiff_t>(src.strideBytes());
  for (int i = 0; i < n; ++i) {
    const int fx = static_cast<int>(weightsX[i] >> 16);
    const int fy = static_cast<int>(weightsY[i] >> 16);
    const std::uint8_t* p0 = base + offset[i];
    const std::uint8_t* p1 = p0 + stride;
    for (int c = 0; c < C; ++c) {
      // Blend along x on both rows, then along y
      const int top = p0[c] * (kOne - fx) + p0[C + c] * fx;
      const int bottom = p1[c] * (kOne - fx) + p1[C + c] * fx;
      dst[i * C + c] =
          static_cast<std::uint8_t>((top * (kOne - fy) + bottom * fy + (1 << (2 * kFracBits - 1))) >> (2 * kFracBits));
    }
  }
}

#if defined(__SSE2__)
/// Four bytes at `p` (unaligned).
inline std::uint32_t load32(const std::uint8_t* p) noexcept {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// RGB gather with SSE2 (part of every x86-64 CPU). Per pixel: each row's left and right
/// neighbours are interleaved as 16-bit lanes, so the x blend of a row is one multiply-add,
/// and the y blend of the two rows another. Reads no byte beyond the right neighbours.
void gatherRowRgbSse2(const Image& src, const std::int32_t* offset, const std::uint32_t* weightsX,
                      const std::uint32_t* weightsY, int n, std::uint8_t* dst) noexcept {
  const std::uint8_t* base = src.row(0);
  const auto stride = static_cast<std::ptrdiff_t>(src.strideBytes());
  const __m128i zero = _mm_setzero_si128();
  constexpr int kShift = 2 * kFracBits - 2;  // x blend: 8 bits, minus 2 dropped, y blend: 8 bits
  const __m128i round = _mm_set1_epi32(1 << (kShift - 1));
  auto pixel = [&](int i) noexcept {
    const std::uint8_t* p0 = base + offset[i];
    const std::uint8_t* p1 = p0 + stride;
    // (1 − f, f) pairs as 16-bit lanes, repeated for the four channel slots
    const __m128i wx = _mm_set1_epi32(static_cast<int>(weightsX[i]));
    const __m128i wy = _mm_set1_epi32(static_cast<int>(weightsY[i]));
    // Rows as [L.r R.r L.g R.g L.b R.b L.x R.x] (the right pixel read from p+2, shifted, so no
    // byte beyond the right neighbour is touched)
    const __m128i row0 = _mm_unpacklo_epi8(_mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(load32(p0))),
                                                             _mm_cvtsi32_si128(static_cast<int>(load32(p0 + 2) >> 8))),
                                           zero);
    const __m128i row1 = _mm_unpacklo_epi8(_mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(load32(p1))),
                                                             _mm_cvtsi32_si128(static_cast<int>(load32(p1 + 2) >> 8))),
                                           zero);
    // x blends (≤ 255·256), 2 bits dropped so the y blend's signed 16-bit inputs cannot overflow
    const __m128i top = _mm_srli_epi32(_mm_madd_epi16(row0, wx), 2);
    const __m128i bottom = _mm_srli_epi32(_mm_madd_epi16(row1, wx), 2);
    // y blend of the interleaved [top bottom] pairs
    const __m128i tb = _mm_unpacklo_epi16(_mm_packs_epi32(top, zero), _mm_packs_epi32(bottom, zero));
    const __m128i px = _mm_srli_epi32(_mm_add_epi32(_mm_madd_epi16(tb, wy), round), kShift);
    const __m128i bytes = _mm_packus_epi16(_mm_packs_epi32(px, zero), zero);
    return static_cast<std::uint32_t>(_mm_cvtsi128_si32(bytes));
  };
  // Four-byte stores (the fourth byte is overwritten by the next pixel); three for the last
  for (int i = 0; i + 1 < n; ++i) {
    const std::uint32_t rgb = pixel(i);
    std::memcpy(dst + 3 * i, &rgb, 4);
  }
  if (n > 0) {
    const std::uint32_t rgb = pixel(n - 1);
    std::memcpy(dst + 3 * (n - 1), &rgb, 3);
  }
}
#endif

void gatherRow(const Image& src, const std::int32_t* offset, const std::uint32_t* weightsX,
               const std::uint32_t* weightsY, int n, std::uint8_t* dst) noexcept {
  if (src.format() == PixelFormat::Rgb8) {
#if defined(__SSE2__)
    gatherRowRgbSse2(src, offset, weightsX, weightsY, n, dst);
#else
    gatherRowScalar<3>(src, offset, weightsX, weightsY, n, dst);
#endif
  } else {
    gatherRowScalar<1>(src, offset, weightsX, weightsY, n, dst);
  }
}

}  // namespace

void RowScratch::reserve(int maxWidthPx) {
  if (maxWidthPx <= mCapacityPx) return;
  // Padded to whole lanes: the forward-difference generator writes in blocks of four.
  const auto n = static_cast<std::size_t>((maxWidthPx + kLanes - 1) / kLanes * kLanes);
  mX.resize(n);
  mY.resize(n);
  mOffset.resize(n);
  mWeightsX.resize(n);
  mWeightsY.resize(n);
  mCapacityPx = maxWidthPx;
}

bool resampleShapesValid(const Image& src, FieldParity parity, int rasterHeightPx, const Image& dst) noexcept {
  if (src.format() != PixelFormat::Grey8 && src.format() != PixelFormat::Rgb8) return false;
  if (src.widthPx() < 2 || src.heightPx() < 2 || src.empty()) return false;
  if (dst.format() != src.format() || dst.widthPx() < 1) return false;
  return rasterHeightPx > 0 && dst.heightPx() == fieldRowCount(parity, rasterHeightPx);
}

double sampleBilinearReference(const Image& src, double x, double y, int c) noexcept {
  const int w = src.widthPx(), h = src.heightPx();
  const int ch = channelsOf(src.format());
  double qx = x - 0.5, qy = y - 0.5;
  qx = qx >= 0.0 ? std::min(qx, w - 1.0) : 0.0;
  qy = qy >= 0.0 ? std::min(qy, h - 1.0) : 0.0;
  const int x0 = std::min(static_cast<int>(qx), w - 2);
  const int y0 = std::min(static_cast<int>(qy), h - 2);
  const double fx = qx - x0, fy = qy - y0;
  auto at = [&](int xi, int yi) { return static_cast<double>(src.row(yi)[xi * ch + c]); };
  const double top = at(x0, y0) * (1.0 - fx) + at(x0 + 1, y0) * fx;
  const double bottom = at(x0, y0 + 1) * (1.0 - fx) + at(x0 + 1, y0 + 1) * fx;
  return top * (1.0 - fy) + bottom * fy;
}

/// The reference loop shared by every map: `map(rasterPx)` per pixel centre, double precision.
template <typename Map>
std::uint32_t resampleReference(const Image& src, const Map& map, FieldParity parity, int rasterHeightPx,
                                Image& dst) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst)) return 0;
  const int w = src.widthPx(), h = src.heightPx(), ch = channelsOf(src.format());
  std::uint32_t violations = 0;
  for (int r = 0; r < dst.heightPx(); ++r) {
    const double v = rasterRow(parity, r) + 0.5;
    std::uint8_t* out = dst.row(r);
    for (int i = 0; i < dst.widthPx(); ++i) {
      const glm::dvec2 p = map({i + 0.5, v});
      const bool inside = p.x >= 0.0 && p.x <= w && p.y >= 0.0 && p.y <= h;
      if (!inside) ++violations;
      for (int c = 0; c < ch; ++c) {
        out[i * ch + c] = static_cast<std::uint8_t>(std::lround(sampleBilinearReference(src, p.x, p.y, c)));
      }
    }
  }
  return violations;
}

std::uint32_t resampleQuadraticReference(const Image& src, const QuadraticMap& map, FieldParity parity,
                                         int rasterHeightPx, Image& dst) noexcept {
  return resampleReference(src, map, parity, rasterHeightPx, dst);
}

std::uint32_t resampleMeshReference(const Image& src, const MeshMap& map, FieldParity parity, int rasterHeightPx,
                                    Image& dst) noexcept {
  return resampleReference(src, map, parity, rasterHeightPx, dst);
}

std::uint32_t sampleRow(const Image& src, const float* framePxX, const float* framePxY, int n, std::uint8_t* dstRow,
                        RowScratch& scratch) noexcept {
  const std::uint32_t violations =
      toSampleOffsets(framePxX, framePxY, n, src, scratch.offset(), scratch.weightsX(), scratch.weightsY());
  gatherRow(src, scratch.offset(), scratch.weightsX(), scratch.weightsY(), n, dstRow);
  return violations;
}

/// Runs `row(firstPx, n, fieldRow, dstPixels)` over the field in vertical strips of kStripPx
/// columns: a rolled or turned map crosses many frame rows along one raster row, and a strip
/// keeps the frame lines it touches in cache from one field row to the next.
template <typename RowFn>
std::uint32_t forEachStrip(Image& dst, RowFn&& row) noexcept {
  constexpr int kStripPx = 128;
  const int channels = channelsOf(dst.format());
  std::uint32_t violations = 0;
  for (int first = 0; first < dst.widthPx(); first += kStripPx) {
    const int n = std::min(kStripPx, dst.widthPx() - first);
    for (int r = 0; r < dst.heightPx(); ++r) violations += row(first, n, r, dst.row(r) + first * channels);
  }
  return violations;
}

std::uint32_t resampleQuadraticFast(const Image& src, const QuadraticMap& map, FieldParity parity, int rasterHeightPx,
                                    Image& dst, RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  return forEachStrip(dst, [&](int first, int n, int r, std::uint8_t* out) noexcept {
    const double v = rasterRow(parity, r) + 0.5;
    quadraticRow(map.a, first, v, n, scratch.x());
    quadraticRow(map.b, first, v, n, scratch.y());
    return sampleRow(src, scratch.x(), scratch.y(), n, out, scratch);
  });
}

std::uint32_t resampleHomography(const Image& src, const Homography& map, FieldParity parity, int rasterHeightPx,
                                 Image& dst, RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  const std::array<double, 9>& h = map.h;
  float* xs = scratch.x();
  float* ys = scratch.y();
  return forEachStrip(dst, [&](int first, int n, int r, std::uint8_t* out) noexcept {
    const double v = rasterRow(parity, r) + 0.5;
    const double nx0 = h[1] * v + h[2], ny0 = h[4] * v + h[5], w0 = h[7] * v + h[8];
    for (int i = 0; i < n; ++i) {
      const double u = first + i + 0.5;
      const double w = h[6] * u + w0;
      // Behind the camera (w ≤ 0) there is nothing to sample: NaN counts as a violation
      const double inv = w > 0.0 ? 1.0 / w : Homography::kNan;
      xs[i] = static_cast<float>((h[0] * u + nx0) * inv);
      ys[i] = static_cast<float>((h[3] * u + ny0) * inv);
    }
    return sampleRow(src, xs, ys, n, out, scratch);
  });
}

std::uint32_t resampleMeshFast(const Image& src, const MeshMap& map, FieldParity parity, int rasterHeightPx, Image& dst,
                               RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  if (map.columns() < 2 || map.rows() < 2) return 0;
  float* xs = scratch.x();
  float* ys = scratch.y();
  return forEachStrip(dst, [&](int first, int n, int r, std::uint8_t* out) noexcept {
    const double v = rasterRow(parity, r) + 0.5;
    const int l = map.cellRow(v);
    const double t = (v - map.nodeYPx(l)) / (map.nodeYPx(l + 1) - map.nodeYPx(l));
    const auto tf = static_cast<float>(t);
    // In a refined cell: the sub-row and the position within it
    const int j = std::clamp(static_cast<int>(t * MeshMap::kSubdivision), 0, MeshMap::kSubdivision - 1);
    const auto ts = static_cast<float>(t * MeshMap::kSubdivision - j);
    // The map along this row at node column k: the cell row's vertical blend
    auto blendX = [&](int k) noexcept { return map.frameX(k, l) + tf * (map.frameX(k, l + 1) - map.frameX(k, l)); };
    auto blendY = [&](int k) noexcept { return map.frameY(k, l) + tf * (map.frameY(k, l + 1) - map.frameY(k, l)); };
    // Pixels [i, end) of the strip from one linear function of u: (ax, ay) at raster u = leftPx,
    // (bx, by) at rightPx
    int i = 0;
    auto emit = [&](int end, double leftPx, double rightPx, float ax, float ay, float bx, float by) noexcept {
      const auto inverseWidth = static_cast<float>(1.0 / (rightPx - leftPx));
      const float dx = (bx - ax) * inverseWidth, dy = (by - ay) * inverseWidth;
      const auto u0 = static_cast<float>(first + 0.5 - leftPx);  // u − left of pixel i = 0
      for (; i < end; ++i) {
        const float du = u0 + static_cast<float>(i);
        xs[i] = ax + dx * du;
        ys[i] = ay + dy * du;
      }
    };
    // Walk the cells the strip crosses; an unrefined cell's right node is the next one's left
    int k = map.cellColumn(first + 0.5);
    float leftX = blendX(k), leftY = blendY(k);
    while (i < n) {
      const int left = map.nodeXPx(k), right = map.nodeXPx(k + 1);
      const float rightX = blendX(k + 1), rightY = blendY(k + 1);
      // Pixel centres before the next node belong to this cell (the last cell takes the rest)
      const int end = k + 2 == map.columns() ? n : std::min(n, right - first);
      if (!map.refined(k, l)) {
        emit(end, left, right, leftX, leftY, rightX, rightY);
      } else {
        for (int s = 0; s < MeshMap::kSubdivision && i < end; ++s) {
          const double subLeft = map.subNodePx(k, l, s, j).x, subRight = map.subNodePx(k, l, s + 1, j).x;
          auto sub = [&](float top, float bottom) noexcept { return top + ts * (bottom - top); };
          const float ax = sub(map.subX(k, l, s, j), map.subX(k, l, s, j + 1));
          const float ay = sub(map.subY(k, l, s, j), map.subY(k, l, s, j + 1));
          const float bx = sub(map.subX(k, l, s + 1, j), map.subX(k, l, s + 1, j + 1));
          const float by = sub(map.subY(k, l, s + 1, j), map.subY(k, l, s + 1, j + 1));
          // Centres before the next sub-node: u + ½ < subRight
          const int subEnd =
              s + 1 == MeshMap::kSubdivision ? end : std::min(end, static_cast<int>(std::ceil(subRight - 0.5)) - first);
          emit(std::max(subEnd, i), subLeft, subRight, ax, ay, bx, by);
        }
      }
      leftX = rightX;
      leftY = rightY;
      ++k;
    }
    return sampleRow(src, xs, ys, n, out, scratch);
  });
}

}  // namespace fieldcast::warp
