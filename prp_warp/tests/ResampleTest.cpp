// The fast kernels against the scalar reference, margin violations and edge fill.
#include "NoiseImage.h"

#include <prp_warp/Resample.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

namespace fieldcast::warp {
namespace {

using test::noiseImage;

int maxAbsDiff(const Image& a, const Image& b) {
  int m = 0;
  for (std::size_t i = 0; i < a.bytes().size(); ++i) m = std::max(m, std::abs(a.bytes()[i] - b.bytes()[i]));
  return m;
}

/// Maps from a 300×200 raster into a 360×250 frame: mild, strong (with violations), rotation.
std::vector<QuadraticMap> someMaps() {
  QuadraticMap mild;
  mild.a = {30.3, 1.01, 0.02, 1e-5, 3e-5, -2e-5};
  mild.b = {25.7, -0.015, 0.99, 2e-5, -1e-5, 4e-5};
  QuadraticMap strong;  // zooms out and shifts: parts fall outside the frame
  strong.a = {-40.0, 1.3, 0.1, 2e-4, 5e-4, -1e-4};
  strong.b = {-20.0, 0.05, 1.25, -3e-4, 1e-4, 6e-4};
  const double c = std::cos(0.3), s = std::sin(0.3);
  QuadraticMap rotation;
  rotation.a = {180.0 - c * 150.0 + s * 100.0, c, -s, 0, 0, 0};
  rotation.b = {125.0 - s * 150.0 - c * 100.0, s, c, 0, 0, 0};
  return {mild, strong, rotation};
}

class FastVersusReference : public ::testing::TestWithParam<std::tuple<PixelFormat, FieldParity>> {};

TEST_P(FastVersusReference, WithinOneGreyLevelAndSameViolations) {
  const auto [format, parity] = GetParam();
  const int rasterW = 300, rasterH = 200;
  const Image src = noiseImage(360, 250, format, 7);  // noise: the worst case for interpolation error
  RowScratch scratch(rasterW);
  for (const QuadraticMap& map : someMaps()) {
    Image fast(rasterW, fieldRowCount(parity, rasterH), format), ref = fast;
    const std::uint32_t vFast = resampleQuadraticFast(src, map, parity, rasterH, fast, scratch);
    const std::uint32_t vRef = resampleQuadraticReference(src, map, parity, rasterH, ref);
    EXPECT_LE(maxAbsDiff(fast, ref), 1);
    EXPECT_EQ(vFast, vRef);
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, FastVersusReference,
                         ::testing::Combine(::testing::Values(PixelFormat::Grey8, PixelFormat::Rgb8),
                                            ::testing::Values(FieldParity::Top, FieldParity::Bottom,
                                                              FieldParity::Progressive)));

TEST(Resample, StrongMapReportsViolationsAndMildMapNone) {
  const Image src = noiseImage(360, 250, PixelFormat::Grey8, 1);
  RowScratch scratch(300);
  Image out(300, 200, PixelFormat::Grey8);
  const auto maps = someMaps();
  EXPECT_EQ(resampleQuadraticFast(src, maps[0], FieldParity::Progressive, 200, out, scratch), 0u);
  EXPECT_GT(resampleQuadraticFast(src, maps[1], FieldParity::Progressive, 200, out, scratch), 1000u);
}

TEST(Resample, IntegerShiftCopiesPixelsExactly) {
  const Image src = noiseImage(64, 48, PixelFormat::Rgb8, 3);
  RowScratch scratch(40);
  Image fast(40, 30, PixelFormat::Rgb8), ref = fast;
  const QuadraticMap shift = QuadraticMap::affine({5.0, 7.0}, {1.0, 1.0});
  EXPECT_EQ(resampleQuadraticFast(src, shift, FieldParity::Progressive, 30, fast, scratch), 0u);
  resampleQuadraticReference(src, shift, FieldParity::Progressive, 30, ref);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40 * 3; ++x) {
      ASSERT_EQ(fast.row(y)[x], src.row(y + 7)[x + 15]);
      ASSERT_EQ(ref.row(y)[x], src.row(y + 7)[x + 15]);
    }
}

TEST(Resample, SamplesOutsideTheFrameAreCountedAndFilledFromTheNearestEdge) {
  const Image src = noiseImage(50, 40, PixelFormat::Grey8, 5);
  RowScratch scratch(20);
  Image out(20, 10, PixelFormat::Grey8);
  // Everything maps 100 px left of the frame, at rows 10..19: the left edge column shows
  const QuadraticMap left = QuadraticMap::affine({-100.0, 10.0}, {1.0, 1.0});
  EXPECT_EQ(resampleQuadraticFast(src, left, FieldParity::Progressive, 10, out, scratch), 200u);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) ASSERT_EQ(out.row(y)[x], src.row(y + 10)[0]);
  // Below the bottom right corner: the corner pixel
  const QuadraticMap corner = QuadraticMap::affine({500.0, 500.0}, {1.0, 1.0});
  EXPECT_EQ(resampleQuadraticReference(src, corner, FieldParity::Progressive, 10, out), 200u);
  for (std::uint8_t b : out.bytes()) ASSERT_EQ(b, src.row(39)[49]);
}

TEST(Resample, HomographyKernelMatchesPerPixelReference) {
  const Image src = noiseImage(360, 250, PixelFormat::Rgb8, 11);
  Homography h;
  h.h = {1.05, 0.04, 20.0, -0.02, 0.98, 15.0, 1e-4, 5e-5, 1.0};
  RowScratch scratch(300);
  Image out(300, 100, PixelFormat::Rgb8);
  const std::uint32_t v = resampleHomography(src, h, FieldParity::Bottom, 200, out, scratch);
  std::uint32_t vRef = 0;
  for (int r = 0; r < 100; ++r)
    for (int i = 0; i < 300; ++i) {
      const glm::dvec2 p = h({i + 0.5, 2 * r + 1 + 0.5});
      if (!(p.x >= 0 && p.x <= 360 && p.y >= 0 && p.y <= 250)) ++vRef;
      for (int c = 0; c < 3; ++c) {
        const double want = sampleBilinearReference(src, p.x, p.y, c);
        ASSERT_LE(std::abs(out.row(r)[3 * i + c] - std::lround(want)), 1) << i << "," << r;
      }
    }
  EXPECT_EQ(v, vRef);
}

/// A mesh over a 300×200 raster into a 360×250 frame: a smooth zoom and shift with a different
/// jitter at every node (so neighbouring cells differ, as at terrain relief), some of it
/// outside the frame.
MeshMap someMesh(int spacingPx, unsigned seed) {
  MeshMap mesh(300, 200, spacingPx);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-3.0, 3.0);
  for (int l = 0; l < mesh.rows(); ++l)
    for (int k = 0; k < mesh.columns(); ++k) {
      mesh.frameX(k, l) = static_cast<float>(-10.0 + 1.2 * mesh.nodeXPx(k) + jitter(rng));
      mesh.frameY(k, l) = static_cast<float>(5.0 + 1.15 * mesh.nodeYPx(l) + 0.05 * mesh.nodeXPx(k) + jitter(rng));
    }
  return mesh;
}

TEST_P(FastVersusReference, MeshWithinOneGreyLevelAndSameViolations) {
  const auto [format, parity] = GetParam();
  const Image src = noiseImage(360, 250, format, 9);
  RowScratch scratch(300);
  // 16 px (the warp's default), 7 px (cells that do not divide the raster, nor the 256 px strips)
  for (int spacing : {16, 7}) {
    const MeshMap mesh = someMesh(spacing, 3);
    Image fast(300, fieldRowCount(parity, 200), format), ref = fast;
    const std::uint32_t vFast = resampleMeshFast(src, mesh, parity, 200, fast, scratch);
    const std::uint32_t vRef = resampleMeshReference(src, mesh, parity, 200, ref);
    EXPECT_LE(maxAbsDiff(fast, ref), 1) << spacing;
    EXPECT_EQ(vFast, vRef) << spacing;
    EXPECT_GT(vRef, 0u) << "the mesh reaches past the frame's left edge";
  }
}

TEST(MeshMap, IsBilinearBetweenNodesAndExactAtThem) {
  const MeshMap mesh = someMesh(16, 5);
  // At a node: the node's value
  EXPECT_NEAR(mesh({32.0, 48.0}).x, mesh.frameX(2, 3), 1e-9);
  EXPECT_NEAR(mesh({32.0, 48.0}).y, mesh.frameY(2, 3), 1e-9);
  // The last node column sits on the raster's edge, not past it
  EXPECT_EQ(mesh.nodeXPx(mesh.columns() - 1), 300);
  EXPECT_EQ(mesh.nodeYPx(mesh.rows() - 1), 200);
  // Mid-cell: the mean of the four corners
  const double mid = 0.25 * (mesh.frameX(2, 3) + mesh.frameX(3, 3) + mesh.frameX(2, 4) + mesh.frameX(3, 4));
  EXPECT_NEAR(mesh({40.0, 56.0}).x, mid, 1e-5);
  // A quarter along a cell's top edge
  EXPECT_NEAR(mesh({36.0, 48.0}).y, 0.75 * mesh.frameY(2, 3) + 0.25 * mesh.frameY(3, 3), 1e-5);
}

TEST(Resample, RejectsMismatchedShapes) {
  const Image src = noiseImage(50, 40, PixelFormat::Grey8, 5);
  Image grey(20, 6, PixelFormat::Grey8), rgb(20, 6, PixelFormat::Rgb8);
  EXPECT_TRUE(resampleShapesValid(src, FieldParity::Top, 11, grey));
  EXPECT_FALSE(resampleShapesValid(src, FieldParity::Bottom, 11, grey));
  EXPECT_FALSE(resampleShapesValid(src, FieldParity::Top, 11, rgb));
}

}  // namespace
}  // namespace fieldcast::warp
