// Least-squares fits of the warp maps to the control points (DESIGN.md §3). The quadratic is the
// seed paper's 12-coefficient map, solved as C = (FᵀF)⁻¹FᵀX through a QR of F on normalised
// coordinates; the homography is the normalised DLT of Hartley & Zisserman (Alg. 4.2).
#include <prp_warp/WarpFit.h>

#include <fieldcast/Conventions.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace fieldcast::warp {
namespace {

// Fixed maximum sizes keep Eigen's storage on the stack: no allocation on the field thread.
using MonomialMatrix = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::ColMajor, kMaxControlPoints, 6>;
using TargetMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::ColMajor, kMaxControlPoints, 2>;

constexpr double kMinDepth = 1e-6;
constexpr double kUsableHalfSizes = 4.0;

bool finite(glm::dvec2 p) noexcept { return std::isfinite(p.x) && std::isfinite(p.y); }

/// A 3×3 Eigen matrix from a glm one (glm is column-major, m[col][row]).
Eigen::Matrix3d toEigen(const glm::dmat3& m) noexcept {
  Eigen::Matrix3d e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e(r, c) = m[c][r];
  return e;
}

/// Homogeneous pixel ← camera direction for the image convention v = cy − fy·y/z.
Eigen::Matrix3d cameraMatrix(const Intrinsics& k) noexcept {
  Eigen::Matrix3d m;
  m << k.fxPx, 0.0, k.cxPx, 0.0, -k.fyPx, k.cyPx, 0.0, 0.0, 1.0;
  return m;
}

/// Similarity that moves the points' centroid to the origin and their mean distance to √2.
Eigen::Matrix3d normalisingTransform(std::span<const glm::dvec2> pts) noexcept {
  glm::dvec2 c{0.0, 0.0};
  for (const glm::dvec2& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  double meanDist = 0.0;
  for (const glm::dvec2& p : pts) meanDist += std::hypot(p.x - c.x, p.y - c.y);
  meanDist /= static_cast<double>(pts.size());
  const double s = meanDist > 0.0 ? std::sqrt(2.0) / meanDist : 1.0;
  Eigen::Matrix3d t;
  t << s, 0.0, -s * c.x, 0.0, s, -s * c.y, 0.0, 0.0, 1.0;
  return t;
}

/// `h` divided by a positive number, so that |h8| = 1 when it can be: the sign of w is kept. (h8 is
/// w at raster (0, 0); dividing by it made w ≤ 0, no sample, over all of a field turned so far
/// from its frame that that corner's ray lies behind the frame's camera.)
Homography scaled(const Eigen::Matrix3d& h) noexcept {
  Homography out;
  const double scale = std::abs(h(2, 2)) > 1e-12 ? std::abs(h(2, 2)) : h.norm();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.h[static_cast<std::size_t>(3 * r + c)] = h(r, c) / scale;
  return out;
}

}  // namespace

Correspondences projectControlPoints(const Frame& frame, const Pose& fieldPose,
                                     const OutputGeometry& geometry) noexcept {
  Correspondences out;
  const Intrinsics& k = geometry.raster;
  const double halfW = 0.5 * k.widthPx, halfH = 0.5 * k.heightPx;
  const std::size_t n = std::min<std::size_t>(frame.controlPoints.size(), kMaxControlPoints);
  for (std::size_t i = 0; i < n; ++i) {
    const ControlPoint& cp = frame.controlPoints[i];
    std::optional<glm::dvec2> px;
    if (cp.kind == ControlPointKind::Surface) {
      px = cameraToPixel(k, worldToCamera(fieldPose, cp.world), kMinDepth);
    } else if (cp.kind == ControlPointKind::Sky) {
      px = cameraToPixel(k, directionToCamera(fieldPose, cp.world), kMinDepth);
    }
    if (!px || !finite(*px) || !finite(cp.framePx)) continue;
    if (std::abs(px->x - halfW) > kUsableHalfSizes * halfW || std::abs(px->y - halfH) > kUsableHalfSizes * halfH)
      continue;
    const auto slot = static_cast<std::size_t>(out.count++);
    out.rasterPx[slot] = *px;
    out.framePx[slot] = cp.framePx;
    if (cp.kind == ControlPointKind::Surface) ++out.surfaceCount;
  }
  return out;
}

std::optional<QuadraticMap> fitQuadratic(std::span<const glm::dvec2> rasterPx, std::span<const glm::dvec2> framePx,
                                         glm::dvec2 centrePx, double halfSizePx) noexcept {
  const auto n = static_cast<Eigen::Index>(std::min(rasterPx.size(), framePx.size()));
  if (n < 6 || n > kMaxControlPoints || !(halfSizePx > 0.0)) return std::nullopt;

  // Monomials of the normalised raster coordinates: x̂ = (u − cu)/s, ŷ = (v − cv)/s.
  const double alpha = 1.0 / halfSizePx;
  const double beta = -centrePx.x * alpha, gamma = -centrePx.y * alpha;
  MonomialMatrix f(n, 6);
  TargetMatrix x(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const glm::dvec2 p = rasterPx[static_cast<std::size_t>(i)];
    const double xn = alpha * p.x + beta, yn = alpha * p.y + gamma;
    f.row(i) << 1.0, xn, yn, xn * yn, xn * xn, yn * yn;
    x(i, 0) = framePx[static_cast<std::size_t>(i)].x;
    x(i, 1) = framePx[static_cast<std::size_t>(i)].y;
  }
  Eigen::ColPivHouseholderQR<MonomialMatrix> qr(f);
  qr.setThreshold(1e-9);
  if (qr.rank() < 6) return std::nullopt;
  const Eigen::Matrix<double, 6, 2> c = qr.solve(x);
  if (!c.allFinite()) return std::nullopt;

  // Expand the normalised polynomial back onto raster pixels (substitute x̂ = αu + β, ŷ = αv + γ).
  QuadraticMap q;
  for (int axis = 0; axis < 2; ++axis) {
    std::array<double, 6>& out = axis == 0 ? q.a : q.b;
    const double c0 = c(0, axis), c1 = c(1, axis), c2 = c(2, axis), c3 = c(3, axis), c4 = c(4, axis), c5 = c(5, axis);
    out[0] = c0 + c1 * beta + c2 * gamma + c3 * beta * gamma + c4 * beta * beta + c5 * gamma * gamma;
    out[1] = c1 * alpha + c3 * alpha * gamma + 2.0 * c4 * alpha * beta;
    out[2] = c2 * alpha + c3 * alpha * beta + 2.0 * c5 * alpha * gamma;
    out[3] = c3 * alpha * alpha;
    out[4] = c4 * alpha * alpha;
    out[5] = c5 * alpha * alpha;
  }
  return q;
}

std::optional<Homography> fitHomography(std::span<const glm::dvec2> rasterPx,
                                        std::span<const glm::dvec2> framePx) noexcept {
  const std::size_t n = std::min(rasterPx.size(), framePx.size());
  if (n < 4) return std::nullopt;
  const Eigen::Matrix3d tSrc = normalisingTransform(rasterPx.first(n));
  const Eigen::Matrix3d tDst = normalisingTransform(framePx.first(n));

  // Accumulate AᵀA of the DLT rows directly: a fixed 9×9, whatever the number of points.
  Eigen::Matrix<double, 9, 9> ata = Eigen::Matrix<double, 9, 9>::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d s = tSrc * Eigen::Vector3d(rasterPx[i].x, rasterPx[i].y, 1.0);
    const Eigen::Vector3d d = tDst * Eigen::Vector3d(framePx[i].x, framePx[i].y, 1.0);
    Eigen::Matrix<double, 9, 1> r1, r2;
    r1 << s.x(), s.y(), 1.0, 0.0, 0.0, 0.0, -d.x() * s.x(), -d.x() * s.y(), -d.x();
    r2 << 0.0, 0.0, 0.0, s.x(), s.y(), 1.0, -d.y() * s.x(), -d.y() * s.y(), -d.y();
    ata.noalias() += r1 * r1.transpose() + r2 * r2.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(ata);
  if (eig.info() != Eigen::Success) return std::nullopt;
  // A unique solution needs a clear gap between the smallest and the next eigenvalue.
  const auto& ev = eig.eigenvalues();
  if (!(ev(1) > 1e-10 * ev(8))) return std::nullopt;
  const Eigen::Matrix<double, 9, 1> v = eig.eigenvectors().col(0);
  Eigen::Matrix3d hn;
  hn << v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7), v(8);
  const Eigen::Matrix3d h = tDst.inverse() * hn * tSrc;
  if (!h.allFinite() || std::abs(h.determinant()) < 1e-300) return std::nullopt;
  // An eigenvector's sign is arbitrary: the one with w > 0 at the fit's own points (seen in the
  // frame), at their centroid
  glm::dvec2 centroid{0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) centroid += rasterPx[i];
  centroid /= static_cast<double>(n);
  const bool behind = h(2, 0) * centroid.x + h(2, 1) * centroid.y + h(2, 2) < 0.0;
  return scaled(behind ? Eigen::Matrix3d(-h) : h);
}

Homography rotationHomography(const Frame& frame, const Pose& fieldPose, const OutputGeometry& geometry) noexcept {
  const Eigen::Matrix3d rFrame = toEigen(worldToCameraRotation(frame.pose));
  const Eigen::Matrix3d rField = toEigen(worldToCameraRotation(fieldPose));
  const Eigen::Matrix3d h =
      cameraMatrix(frame.intrinsics) * rFrame * rField.transpose() * cameraMatrix(geometry.raster).inverse();
  // w is the depth in the frame's camera of the field pixel's ray: its sign is right as made
  return scaled(h);
}

QuadraticFit fitFieldQuadratic(const Frame& frame, const Pose& fieldPose, const OutputGeometry& geometry) noexcept {
  QuadraticFit fit;
  const Correspondences c = projectControlPoints(frame, fieldPose, geometry);
  fit.usablePoints = c.count;
  const auto n = static_cast<std::size_t>(c.count);
  if (c.count < 6) {
    fit.outcome = FitOutcome::FallbackFewPoints;
  } else if (c.surfaceCount == 0) {
    fit.outcome = FitOutcome::FallbackAllSky;
  } else {
    const glm::dvec2 centre{0.5 * geometry.raster.widthPx, 0.5 * geometry.raster.heightPx};
    const double halfSize = 0.5 * std::max(geometry.raster.widthPx, geometry.raster.heightPx);
    if (auto q = fitQuadratic(std::span(c.rasterPx).first(n), std::span(c.framePx).first(n), centre, halfSize)) {
      fit.quadratic = *q;
      return fit;
    }
    fit.outcome = FitOutcome::FallbackDegenerate;
  }
  fit.homography = rotationHomography(frame, fieldPose, geometry);
  return fit;
}

}  // namespace fieldcast::warp
