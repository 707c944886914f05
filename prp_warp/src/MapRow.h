#pragma once
// A raster row's frame coordinates under a quadratic map or a homography, pixel by pixel: the
// scalar references of the vector kernels (MapRowLanes.cpp), which must give the same floats.

#include <array>
#include <limits>

namespace fieldcast::warp::mapping {

/// The longest run of a raster row the kernels evaluate a map on: the width of the strips the
/// field is resampled in (Resample.cpp's forEachStrip).
constexpr int kMaxRunPx = 256;

/// Along a raster row a quadratic map is a parabola in the pixel's position. For pixel i of a run
/// (centre u = i + ½ from the run's start) it is a + u·(b + u·c), in single precision: the
/// coefficients are worked out per run in double about its first pixel, so u stays small (a run
/// is at most kMaxRunPx pixels) and the error below 1e-3 px: one rounding of a, a few of terms no
/// larger than the run's span in the frame (kMaxRunPx times the map's scale).
inline float parabolaAt(float a, float b, float c, int i) noexcept {
  const float u = static_cast<float>(i) + 0.5f;
  return a + u * (b + u * c);
}

/// parabolaAt for pixels first … n − 1 of a run into out[first …].
inline void parabolaRowScalar(float a, float b, float c, int first, int n, float* out) noexcept {
  for (int i = first; i < n; ++i) out[i] = parabolaAt(a, b, c, i);
}

/// parabolaRowScalar for pixels 0 … n − 1 in SIMD lanes at the dispatched level: the same floats
/// (the same operations in the same order, none fused: the build turns contraction off).
void parabolaRowLanes(float a, float b, float c, int n, float* out) noexcept;

/// One frame coordinate (x or y: that map's coefficients `c`, QuadraticMap's order) of the pixel
/// centres firstPx + i + ½, i < n, of raster row v (its centre): along the row the map is a
/// parabola A + B·U + C·U² in the raster's U, about the run's first pixel (U = firstPx + u)
/// a + b·u + c·u², worked out in double and evaluated in lanes (parabolaRowLanes).
inline void quadraticRow(const std::array<double, 6>& c, int firstPx, double v, int n, float* out) noexcept {
  const double a = c[0] + c[2] * v + c[5] * v * v;
  const double b = c[1] + c[3] * v;
  const double cc = c[4];
  const double f = firstPx;
  parabolaRowLanes(static_cast<float>(a + f * (b + f * cc)), static_cast<float>(b + 2.0 * cc * f),
                   static_cast<float>(cc), n, out);
}

/// Along a raster row a homography is a ratio of straight lines in the pixel's position: for
/// pixel i of a run (u = i + ½ from the run's first pixel) x = (ax + bx·u) / (aw + bw·u) and
/// y = (ay + by·u) / (aw + bw·u), in single precision about the run's first pixel (the lines'
/// values there worked out in double), NaN where the denominator is not positive (the point lies
/// behind the camera; NaN counts as a margin violation).
struct RatioRow {
  float ax, bx, ay, by, aw, bw;
};

inline void ratioAt(const RatioRow& r, int i, float& x, float& y) noexcept {
  const float u = static_cast<float>(i) + 0.5f;
  const float w = r.aw + r.bw * u;
  const bool ahead = w > 0.0f;  // false for NaN
  x = ahead ? (r.ax + r.bx * u) / w : std::numeric_limits<float>::quiet_NaN();
  y = ahead ? (r.ay + r.by * u) / w : std::numeric_limits<float>::quiet_NaN();
}

/// ratioAt for pixels first … n − 1 of a run into xs[first …], ys[first …].
inline void ratioRowScalar(const RatioRow& r, int first, int n, float* xs, float* ys) noexcept {
  for (int i = first; i < n; ++i) ratioAt(r, i, xs[i], ys[i]);
}

/// ratioRowScalar for pixels 0 … n − 1 in SIMD lanes at the dispatched level: the same floats.
void ratioRowLanes(const RatioRow& r, int n, float* xs, float* ys) noexcept;

/// The frame coordinates of the pixel centres firstPx + i + ½, i < n, of raster row v (its centre)
/// under the homography `h` (Homography's row-major order), evaluated in lanes (ratioRowLanes).
inline void homographyRow(const std::array<double, 9>& h, int firstPx, double v, int n, float* xs, float* ys) noexcept {
  const double u0 = firstPx;  // the lines' values at the run's first pixel's left edge
  const RatioRow r{static_cast<float>(h[0] * u0 + h[1] * v + h[2]), static_cast<float>(h[0]),
                   static_cast<float>(h[3] * u0 + h[4] * v + h[5]), static_cast<float>(h[3]),
                   static_cast<float>(h[6] * u0 + h[7] * v + h[8]), static_cast<float>(h[6])};
  ratioRowLanes(r, n, xs, ys);
}

}  // namespace fieldcast::warp::mapping
