#pragma once
// Bilinear resampling of a frame through a map into the rows of one field (DESIGN.md §3).
//
// Every kernel follows the same rules, so they can be compared pixel for pixel:
//  - field row r is raster row rasterRow(parity, r); its pixel i is sampled at the map of the
//    raster point (i + ½, row + ½);
//  - a map value outside the frame ([0, W] × [0, H] in frame pixels, or NaN) is a margin
//    violation: it is counted and the sample is clamped to the nearest edge of the frame;
//  - the source and the field image have the same pixel format (Grey8 or Rgb8).

#include <prp_warp/FieldRows.h>
#include <prp_warp/MeshMap.h>
#include <prp_warp/WarpMaps.h>

#include <fieldcast/Field.h>
#include <fieldcast/Image.h>

#include <cstdint>
#include <vector>

namespace fieldcast::warp {

/// Per-row work buffers of the fast kernels, sized once for the widest raster. Not shared
/// between threads.
class RowScratch {
 public:
  /// Allocates for rows up to `maxWidthPx` pixels.
  explicit RowScratch(int maxWidthPx = 0) { reserve(maxWidthPx); }
  /// Grows the buffers (allocates; not for the field thread).
  void reserve(int maxWidthPx);
  int capacityPx() const noexcept { return mCapacityPx; }

  /// Frame coordinates of a row (float: exact to 1e-4 px over any frame, and twice the lanes).
  float* x() noexcept { return mX.data(); }
  float* y() noexcept { return mY.data(); }

 private:
  int mCapacityPx = 0;
  std::vector<float> mX, mY;
};

/// True when `dst` is the right shape for a field of `parity` of a raster `rasterHeightPx` high
/// and `src` can be sampled (same format, Grey8 or Rgb8, at least 2 × 2). RT-safe.
bool resampleShapesValid(const Image& src, FieldParity parity, int rasterHeightPx, const FieldRows& dst) noexcept;

/// The plain reference: evaluates the quadratic at every pixel and interpolates in double
/// precision. Returns the margin violations. RT-safe.
std::uint32_t resampleQuadraticReference(const Image& src, const QuadraticMap& map, FieldParity parity,
                                         int rasterHeightPx, FieldRows dst) noexcept;

/// The fast kernel: the quadratic evaluated along each run of a row in single precision in SIMD
/// lanes (the same floats at every level), then fixed-point (8-bit) bilinear sampling. Matches
/// the reference within one grey level. Returns the margin violations. RT-safe (scratch must be
/// wide enough).
std::uint32_t resampleQuadraticFast(const Image& src, const QuadraticMap& map, FieldParity parity, int rasterHeightPx,
                                    FieldRows dst, RowScratch& scratch) noexcept;

/// Homography resampling: the map along each run of a row in SIMD lanes (one division per pixel,
/// single precision, mapping::homographyRow), then the fast kernel's sampling. RT-safe.
std::uint32_t resampleHomography(const Image& src, const Homography& map, FieldParity parity, int rasterHeightPx,
                                 FieldRows dst, RowScratch& scratch) noexcept;

/// Depth-mesh reference: evaluates the bilinear cell map at every pixel and interpolates in
/// double precision. Returns the margin violations. RT-safe.
std::uint32_t resampleMeshReference(const Image& src, const MeshMap& map, FieldParity parity, int rasterHeightPx,
                                    FieldRows dst) noexcept;

/// Depth-mesh fast kernel: per cell, one linear function of u along the row (blended once from
/// the cell's four nodes), then the shared fixed-point sampling. Matches the reference within
/// one grey level. Returns the margin violations. RT-safe (scratch must be wide enough).
std::uint32_t resampleMeshFast(const Image& src, const MeshMap& map, FieldParity parity, int rasterHeightPx,
                               FieldRows dst, RowScratch& scratch) noexcept;

/// Samples `src` at the given frame pixel coordinates for one row of `n` pixels into `dstRow`
/// (bilinear in 1/256 px and 1/65536 of a grey level, edge clamp). Returns the margin
/// violations. The shared last stage of every fast kernel, in SIMD lanes at the dispatched level
/// (fieldcast/SimdLevel.h). RT-safe.
std::uint32_t sampleRow(const Image& src, const float* framePxX, const float* framePxY, int n,
                        std::uint8_t* dstRow) noexcept;

/// sampleRow pixel by pixel in plain C++: the judge of its SIMD forms, which give the same bytes
/// and violations. RT-safe.
std::uint32_t sampleRowReference(const Image& src, const float* framePxX, const float* framePxY, int n,
                                 std::uint8_t* dstRow) noexcept;

/// Reference bilinear sample of channel `c` of `src` at frame pixel `(x, y)` (clamped to the
/// frame), in grey levels. RT-safe.
double sampleBilinearReference(const Image& src, double x, double y, int c) noexcept;

}  // namespace fieldcast::warp
