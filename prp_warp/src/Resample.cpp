// Bilinear resampling kernels. The reference evaluates the map per pixel in double precision;
// the fast path splits each row into three short loops a compiler vectorises: generate the
// frame coordinates (forward differences for the quadratic), convert them to 10-bit fixed point
// while counting margin violations, then gather and blend in integers.
#include <prp_warp/Resample.h>

#include <algorithm>
#include <cmath>

namespace fieldcast::warp {
namespace {

constexpr int kFracBits = 10;
constexpr int kOne = 1 << kFracBits;
constexpr int kLanes = 4;

int channelsOf(PixelFormat f) noexcept { return f == PixelFormat::Rgb8 ? 3 : 1; }

/// Frame x coordinates of pixel centres i + ½ of one raster row under a quadratic, stepped by
/// forward differences: lane j holds pixels j, j+4, j+8, …; each lane advances by its first
/// difference, which advances by the constant second difference.
void quadraticRow(const std::array<double, 6>& c, double v, int n, double* out) noexcept {
  // Along the row the map is a parabola in u: A + B·u + C·u².
  const double a = c[0] + c[2] * v + c[5] * v * v;
  const double b = c[1] + c[3] * v;
  const double cc = c[4];
  auto at = [&](int i) noexcept {
    const double u = i + 0.5;
    return a + b * u + cc * u * u;
  };
  double value[kLanes], step[kLanes];
  for (int j = 0; j < kLanes; ++j) {
    value[j] = at(j);
    step[j] = at(j + kLanes) - at(j);
  }
  const double stepStep = at(2 * kLanes) - 2.0 * at(kLanes) + at(0);
  for (int i = 0; i < n; i += kLanes) {
    // Emit four pixels, then climb every lane to its next pixel
    for (int j = 0; j < kLanes; ++j) {
      out[i + j] = value[j];
      value[j] += step[j];
      step[j] += stepStep;
    }
  }
}

/// Converts frame coordinates to fixed point sample positions (pixel-centre origin), clamped
/// to the frame, and counts the coordinates outside the frame (NaN included).
std::uint32_t toFixedPoint(const double* x, const double* y, int n, int w, int h, std::int32_t* ix,
                           std::int32_t* iy) noexcept {
  const double maxX = w - 1.0, maxY = h - 1.0;
  std::uint32_t violations = 0;
  for (int i = 0; i < n; ++i) {
    const double px = x[i], py = y[i];
    const bool inside = px >= 0.0 && px <= w && py >= 0.0 && py <= h;
    violations += inside ? 0u : 1u;
    // Written so that NaN clamps to 0: a comparison with NaN is false
    double qx = px - 0.5, qy = py - 0.5;
    qx = qx >= 0.0 ? qx : 0.0;
    qy = qy >= 0.0 ? qy : 0.0;
    qx = qx <= maxX ? qx : maxX;
    qy = qy <= maxY ? qy : maxY;
    ix[i] = static_cast<std::int32_t>(qx * kOne + 0.5);
    iy[i] = static_cast<std::int32_t>(qy * kOne + 0.5);
  }
  return violations;
}

/// Fixed-point bilinear gather of one row; positions already clamped to [0, W−1] × [0, H−1].
template <int C>
void gatherRow(const Image& src, const std::int32_t* ix, const std::int32_t* iy, int n, std::uint8_t* dst) noexcept {
  const std::uint8_t* base = src.row(0);
  const auto stride = static_cast<std::ptrdiff_t>(src.strideBytes());
  const int lastX = src.widthPx() - 2, lastY = src.heightPx() - 2;
  for (int i = 0; i < n; ++i) {
    const int x0 = std::min(ix[i] >> kFracBits, lastX);
    const int y0 = std::min(iy[i] >> kFracBits, lastY);
    const int fx = ix[i] - (x0 << kFracBits);
    const int fy = iy[i] - (y0 << kFracBits);
    const std::uint8_t* p0 = base + y0 * stride + x0 * C;
    const std::uint8_t* p1 = p0 + stride;
    for (int c = 0; c < C; ++c) {
      // Blend along x on both rows, then along y; 10 + 10 fraction bits fit in 32 bits
      const int top = p0[c] * (kOne - fx) + p0[C + c] * fx;
      const int bottom = p1[c] * (kOne - fx) + p1[C + c] * fx;
      dst[i * C + c] =
          static_cast<std::uint8_t>((top * (kOne - fy) + bottom * fy + (1 << (2 * kFracBits - 1))) >> (2 * kFracBits));
    }
  }
}

}  // namespace

void RowScratch::reserve(int maxWidthPx) {
  if (maxWidthPx <= mCapacityPx) return;
  // Padded to whole lanes: the forward-difference generator writes in blocks of four.
  const auto n = static_cast<std::size_t>((maxWidthPx + kLanes - 1) / kLanes * kLanes);
  mX.resize(n);
  mY.resize(n);
  mIx.resize(n);
  mIy.resize(n);
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

std::uint32_t resampleQuadraticReference(const Image& src, const QuadraticMap& map, FieldParity parity,
                                         int rasterHeightPx, Image& dst) noexcept {
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

std::uint32_t sampleRow(const Image& src, const double* framePxX, const double* framePxY, int n, std::uint8_t* dstRow,
                        RowScratch& scratch) noexcept {
  const std::uint32_t violations =
      toFixedPoint(framePxX, framePxY, n, src.widthPx(), src.heightPx(), scratch.ix(), scratch.iy());
  if (src.format() == PixelFormat::Rgb8) {
    gatherRow<3>(src, scratch.ix(), scratch.iy(), n, dstRow);
  } else {
    gatherRow<1>(src, scratch.ix(), scratch.iy(), n, dstRow);
  }
  return violations;
}

std::uint32_t resampleQuadraticFast(const Image& src, const QuadraticMap& map, FieldParity parity, int rasterHeightPx,
                                    Image& dst, RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  const int n = dst.widthPx();
  std::uint32_t violations = 0;
  for (int r = 0; r < dst.heightPx(); ++r) {
    const double v = rasterRow(parity, r) + 0.5;
    quadraticRow(map.a, v, n, scratch.x());
    quadraticRow(map.b, v, n, scratch.y());
    violations += sampleRow(src, scratch.x(), scratch.y(), n, dst.row(r), scratch);
  }
  return violations;
}

std::uint32_t resampleHomography(const Image& src, const Homography& map, FieldParity parity, int rasterHeightPx,
                                 Image& dst, RowScratch& scratch) noexcept {
  if (!resampleShapesValid(src, parity, rasterHeightPx, dst) || scratch.capacityPx() < dst.widthPx()) return 0;
  const int n = dst.widthPx();
  const std::array<double, 9>& h = map.h;
  double* xs = scratch.x();
  double* ys = scratch.y();
  std::uint32_t violations = 0;
  for (int r = 0; r < dst.heightPx(); ++r) {
    const double v = rasterRow(parity, r) + 0.5;
    const double nx0 = h[1] * v + h[2], ny0 = h[4] * v + h[5], w0 = h[7] * v + h[8];
    for (int i = 0; i < n; ++i) {
      const double u = i + 0.5;
      const double w = h[6] * u + w0;
      // Behind the camera (w ≤ 0) there is nothing to sample: NaN counts as a violation
      const double inv = w > 0.0 ? 1.0 / w : Homography::kNan;
      xs[i] = (h[0] * u + nx0) * inv;
      ys[i] = (h[3] * u + ny0) * inv;
    }
    violations += sampleRow(src, xs, ys, n, dst.row(r), scratch);
  }
  return violations;
}

}  // namespace fieldcast::warp
