// Bilinear resampling kernels. The reference evaluates the map per pixel in double precision;
// the fast path generates each row's frame coordinates (in lanes for the quadratic, MapRow.h)
// and samples them in fixed point, in SIMD lanes at the dispatched level (ResampleLanes.cpp;
// its scalar reference in SamplePixel.h).
#include <prp_warp/Resample.h>

#include "MapRow.h"
#include "SamplePixel.h"

#include <algorithm>
#include <cmath>

namespace fieldcast::warp {
namespace {

int channelsOf(PixelFormat f) noexcept { return f == PixelFormat::Rgb8 ? 3 : 1; }

sampling::Source sourceOf(const Image& src) noexcept {
  return {src.row(0), static_cast<std::int32_t>(src.strideBytes()), src.widthPx(), src.heightPx()};
}

}  // namespace

void RowScratch::reserve(int maxWidthPx) {
  if (maxWidthPx <= mCapacityPx) return;
  const auto n = static_cast<std::size_t>(maxWidthPx);
  mX.resize(n);
  mY.resize(n);
  mCapacityPx = maxWidthPx;
}

bool resampleShapesValid(const Image& src, FieldParity parity, int rasterHeightPx, const FieldRows& dst) noexcept {
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
                                FieldRows dst) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst)) return 0;
  const int w = src.widthPx(), h = src.heightPx(), ch = channelsOf(src.format());
  std::uint32_t violations = 0;
  for (int r = 0; r < dst.heightPx(); ++r) {
    const double v = rasterRow(parity, r) + 0.5;
    std::uint8_t* out = dst.begin(0, r);
    for (int i = 0; i < dst.widthPx(); ++i) {
      const glm::dvec2 p = map({i + 0.5, v});
      const bool inside = p.x >= 0.0 && p.x <= w && p.y >= 0.0 && p.y <= h;
      if (!inside) ++violations;
      for (int c = 0; c < ch; ++c) {
        out[i * ch + c] = static_cast<std::uint8_t>(std::lround(sampleBilinearReference(src, p.x, p.y, c)));
      }
    }
    dst.end(0, dst.widthPx(), r);
  }
  return violations;
}

std::uint32_t resampleQuadraticReference(const Image& src, const QuadraticMap& map, FieldParity parity,
                                         int rasterHeightPx, FieldRows dst) noexcept {
  return resampleReference(src, map, parity, rasterHeightPx, dst);
}

std::uint32_t resampleMeshReference(const Image& src, const MeshMap& map, FieldParity parity, int rasterHeightPx,
                                    FieldRows dst) noexcept {
  return resampleReference(src, map, parity, rasterHeightPx, dst);
}

/// Asks for the frame lines the samples of a row a few frame rows further down will read. The
/// vector kernel reads the frame by gathers, which the CPU's prefetchers do not follow, and a
/// field row needs new frame lines at every row: without this a 1080i field waited on memory for
/// most of its time (fieldcast_bench_warp, AVX-512, the kernel alone: 3.6 ms with it, 6.1–7.1 ms
/// without). For the maps of a field (rolled less than 90°; a mirror is applied after the warp) a
/// field's next rows lie further down the frame; for others the prefetch is wasted, not wrong.
/// Inlined on purpose: as a call, measured the same, it gained nothing.
[[gnu::always_inline]] inline void prefetchRowsAhead(const Image& src, const float* framePxX, const float* framePxY,
                                                     int n) noexcept {
  constexpr float kRowsAhead = 6.0f;  // three field rows; 3 to 10 measured the same
  const int channels = channelsOf(src.format());
  const auto width = static_cast<float>(src.widthPx()), lastRow = static_cast<float>(src.heightPx() - 1);
  for (int i = 0; i < n; i += 64 / channels) {
    const float x = framePxX[i], y = framePxY[i] + kRowsAhead;
    if (x >= 0.0f && x < width && y >= 0.0f && y < lastRow) {  // false for NaN
      const std::uint8_t* p = src.row(static_cast<int>(y)) + static_cast<int>(x) * channels;
      __builtin_prefetch(p);
      __builtin_prefetch(p + src.strideBytes());
    }
  }
}

std::uint32_t sampleRow(const Image& src, const float* framePxX, const float* framePxY, int n,
                        std::uint8_t* dstRow) noexcept {
  prefetchRowsAhead(src, framePxX, framePxY, n);
  return sampling::sampleRowLanes(sourceOf(src), channelsOf(src.format()), framePxX, framePxY, n, dstRow);
}

std::uint32_t sampleRowReference(const Image& src, const float* framePxX, const float* framePxY, int n,
                                 std::uint8_t* dstRow) noexcept {
  return src.format() == PixelFormat::Rgb8 ? sampling::sampleRowScalar<3>(sourceOf(src), framePxX, framePxY, n, dstRow)
                                           : sampling::sampleRowScalar<1>(sourceOf(src), framePxX, framePxY, n, dstRow);
}

/// Runs `row(firstPx, n, fieldRow, dstPixels)` over the field in vertical strips of kStripPx
/// columns: a rolled or turned map crosses many frame rows along one raster row, and a strip
/// keeps the frame lines it touches in cache from one field row to the next. 256 columns: the
/// NTSC field step 0.30 -> 0.28 ms against 128 (half the calls per field); 512 and whole
/// rows measured the same at NTSC, a 1080i strip of 256 already about fills a 1 MB L2.
template <typename RowFn>
std::uint32_t forEachStrip(FieldRows dst, RowFn&& row) noexcept {
  constexpr int kStripPx = mapping::kMaxRunPx;
  std::uint32_t violations = 0;
  for (int first = 0; first < dst.widthPx(); first += kStripPx) {
    const int n = std::min(kStripPx, dst.widthPx() - first);
    for (int r = 0; r < dst.heightPx(); ++r) {
      violations += row(first, n, r, dst.begin(first, r));
      dst.end(first, n, r);
    }
  }
  return violations;
}

std::uint32_t resampleQuadraticFast(const Image& src, const QuadraticMap& map, FieldParity parity, int rasterHeightPx,
                                    FieldRows dst, RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  return forEachStrip(dst, [&](int first, int n, int r, std::uint8_t* out) noexcept {
    const double v = rasterRow(parity, r) + 0.5;
    mapping::quadraticRow(map.a, first, v, n, scratch.x());
    mapping::quadraticRow(map.b, first, v, n, scratch.y());
    return sampleRow(src, scratch.x(), scratch.y(), n, out);
  });
}

std::uint32_t resampleHomography(const Image& src, const Homography& map, FieldParity parity, int rasterHeightPx,
                                 FieldRows dst, RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  return forEachStrip(dst, [&](int first, int n, int r, std::uint8_t* out) noexcept {
    mapping::homographyRow(map.h, first, rasterRow(parity, r) + 0.5, n, scratch.x(), scratch.y());
    return sampleRow(src, scratch.x(), scratch.y(), n, out);
  });
}

std::uint32_t resampleMeshFast(const Image& src, const MeshMap& map, FieldParity parity, int rasterHeightPx,
                               FieldRows dst, RowScratch& scratch) noexcept {
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
    return sampleRow(src, xs, ys, n, out);
  });
}

}  // namespace fieldcast::warp
