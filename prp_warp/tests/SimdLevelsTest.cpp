// The warp's vector kernels at every SIMD level this machine runs, each against its scalar
// reference: the same bytes and margin violations (the map's rows: the same floats, and their
// error against the map).
#include <prp_warp/PostProcess.h>
#include "FlickerRow.h"
#include "MapRow.h"
#include "NoiseImage.h"
#include "SampleBlockVbmi.h"

#include "../../tests/common/AtEverySimdLevel.h"

#include <prp_warp/Resample.h>
#include <prp_warp/WarpMaps.h>

#include <fieldcast/SimdLevel.h>

#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace fieldcast::warp {
namespace {

using test::noiseImage;

/// Sample coordinates that drive every clamp: inside, on and past each edge, NaN, infinities,
/// huge values, exact pixel centres and the last 1/256 px before the edge.
std::vector<float> coordinates(int n, float size, std::mt19937& rng) {
  std::uniform_real_distribution<float> inside(0.0f, size), wide(-0.3f * size, 1.3f * size);
  const float special[] = {0.0f,
                           0.5f,
                           size,
                           size - 0.5f,
                           size - 1.0f / 512.0f,
                           -1e-7f,
                           std::nextafter(size, 2.0f * size),
                           std::numeric_limits<float>::quiet_NaN(),
                           std::numeric_limits<float>::infinity(),
                           -std::numeric_limits<float>::infinity(),
                           3e9f,
                           -3e9f};
  std::vector<float> out(static_cast<std::size_t>(n));
  for (float& v : out) {
    const auto pick = static_cast<unsigned>(rng() % 10);
    v = pick < 6 ? inside(rng) : pick < 9 ? wide(rng) : special[static_cast<std::size_t>(rng()) % std::size(special)];
  }
  return out;
}

/// Calls blocks(source) with a frame `width` × `height` pixels of `channels` (random bytes, rows
/// padded by a byte) whose last byte is the neighbour of a page that may not be read: a read past
/// the frame's end stops the test.
template <typename Blocks>
void withGuardedFrame(int channels, int width, int height, const Blocks& blocks) {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const int stride = width * channels + 1;
  const std::size_t frameBytes = static_cast<std::size_t>((height - 1) * stride + width * channels);
  const std::size_t pages = (frameBytes + page - 1) / page;
  auto* area = static_cast<std::uint8_t*>(
      ::mmap(nullptr, (pages + 1) * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(area, MAP_FAILED);
  std::uint8_t* guard = area + pages * page;
  ASSERT_EQ(::mprotect(guard, page, PROT_NONE), 0);
  std::uint8_t* base = guard - frameBytes;
  std::mt19937 rng(5);
  for (std::uint8_t* b = base; b < guard; ++b) *b = static_cast<std::uint8_t>(rng());
  blocks(sampling::Source{base, stride, width, height});
  ASSERT_EQ(::munmap(area, (pages + 1) * page), 0);
}

TEST(SimdLevels, SampleRowGivesTheReferencesBytesAndViolations) {
  fieldcast::testing::atEverySimdLevel([] {
    std::mt19937 rng(11);
    for (const PixelFormat format : {PixelFormat::Rgb8, PixelFormat::Grey8}) {
      const int channels = format == PixelFormat::Rgb8 ? 3 : 1;
      for (const auto& [w, h] : {std::pair{2, 2}, std::pair{3, 5}, std::pair{37, 19}, std::pair{360, 250}}) {
        const Image src = noiseImage(w, h, format, static_cast<unsigned>(w * h));
        for (int n = 1; n <= 70; n += 3) {  // every tail length of every vector width
          const std::vector<float> xs = coordinates(n, static_cast<float>(w), rng);
          const std::vector<float> ys = coordinates(n, static_cast<float>(h), rng);
          std::vector<std::uint8_t> fast(static_cast<std::size_t>(n * channels) + 1, 0xA5), ref = fast;
          const std::uint32_t vFast = sampleRow(src, xs.data(), ys.data(), n, fast.data());
          const std::uint32_t vRef = sampleRowReference(src, xs.data(), ys.data(), n, ref.data());
          ASSERT_EQ(fast, ref) << "frame " << w << "x" << h << ", " << channels << " channels, " << n << " pixels";
          ASSERT_EQ(vFast, vRef);
        }
      }
    }
  });
}

// The short cut for a block whose every sample lies between the frame's outer pixel centres (no
// violation, no clamp that changes a byte), staged and gathered: blocks with a lane on each edge
// of that region, just inside it and just past it, in a frame that ends at a page that may not be
// read, give the reference's bytes and violations at every level.
TEST(SimdLevels, TheSamplingsShortCutEndsWhereAClampWouldChangeASample) {
  const int width = 64, height = 12;
  const auto w = static_cast<float>(width), h = static_cast<float>(height);
  // An edge lane's value: on the short cut's edge, either side of it, and on or past the frame's
  const float left[] = {0.5f, std::nextafter(0.5f, 0.0f), 0.25f, 0.0f, -0.25f};
  const float right[] = {w - 1.5f, w - 0.5f, std::nextafter(w - 0.5f, w), w - 0.375f, w, std::nextafter(w, 2.0f * w)};
  const float top[] = {0.5f, std::nextafter(0.5f, 0.0f), 0.25f, -0.25f};
  const float bottom[] = {h - 1.5f, h - 0.5f, std::nextafter(h - 0.5f, h), h - 0.375f, h + 0.25f};
  struct Block {
    std::array<float, 16> xs, ys;
    bool staged;  // a block reaching the last row may be refused: its loads would pass the frame
  };
  std::vector<Block> blocks;
  std::array<float, 16> midRows{}, midColumns{};
  for (int i = 0; i < 16; ++i) {
    midRows[static_cast<std::size_t>(i)] = 5.3f + 0.05f * static_cast<float>(i);
    midColumns[static_cast<std::size_t>(i)] = 20.2f + 0.9f * static_cast<float>(i);
  }
  for (const float x : left) {
    Block b{{}, midRows, true};
    for (int i = 0; i < 16; ++i) b.xs[static_cast<std::size_t>(i)] = x + 0.9f * static_cast<float>(i);
    blocks.push_back(b);
  }
  for (const float x : right) {
    Block b{{}, midRows, true};
    for (int i = 0; i < 16; ++i) b.xs[static_cast<std::size_t>(i)] = x - 0.9f * static_cast<float>(15 - i);
    blocks.push_back(b);
  }
  for (const float y : top) {
    Block b{midColumns, {}, true};
    for (int i = 0; i < 16; ++i) b.ys[static_cast<std::size_t>(i)] = y + 0.06f * static_cast<float>(15 - i);
    blocks.push_back(b);
  }
  for (const float y : bottom) {
    Block b{midColumns, {}, false};
    for (int i = 0; i < 16; ++i) b.ys[static_cast<std::size_t>(i)] = y - 0.06f * static_cast<float>(15 - i);
    blocks.push_back(b);
  }
  // The last corner: the gathered short cut's lower right, where a read of the right neighbour's
  // lower row past its bound would run into the unreadable page
  for (const float x : right) {
    Block b{{}, {}, false};
    for (int i = 0; i < 16; ++i) {
      b.xs[static_cast<std::size_t>(i)] = x - 0.9f * static_cast<float>(15 - i);
      b.ys[static_cast<std::size_t>(i)] = h - 1.5f;
    }
    blocks.push_back(b);
  }
  for (const int channels : {3, 1}) {
    withGuardedFrame(channels, width, height, [&](const sampling::Source& src) {
      for (const Block& b : blocks) {
        const auto bytes = static_cast<std::size_t>(16 * channels);
        std::vector<std::uint8_t> ref(bytes), fast(bytes), row(bytes);
        const std::uint32_t refViolations =
            channels == 3 ? sampling::sampleRowScalar<3>(src, b.xs.data(), b.ys.data(), 16, ref.data())
                          : sampling::sampleRowScalar<1>(src, b.xs.data(), b.ys.data(), 16, ref.data());
        const std::string where = std::to_string(channels) + " channels, x " + std::to_string(b.xs[0]) + ".." +
                                  std::to_string(b.xs[15]) + ", y " + std::to_string(b.ys[0]) + ".." +
                                  std::to_string(b.ys[15]);
        if (simdVbmiEnabled()) {
          std::uint32_t violations = 0;
          if (sampling::sampleBlocksVbmi(src, channels, b.xs.data(), b.ys.data(), 16, fast.data(), violations) == 16) {
            EXPECT_EQ(fast, ref) << where;
            EXPECT_EQ(violations, refViolations) << where;
          } else {
            EXPECT_FALSE(b.staged) << "refused: " << where;
          }
        }
        fieldcast::testing::atEverySimdLevel([&] {
          EXPECT_EQ(sampling::sampleRowLanes(src, channels, b.xs.data(), b.ys.data(), 16, row.data()), refViolations)
              << where;
          EXPECT_EQ(row, ref) << where;
        });
      }
    });
  }
}

// Rows as a field's map makes them (turned, scaled, mirrored, at the frame's edges), where the
// avx512vbmi level stages a block's frame bytes in registers, and where it cannot and gathers.
TEST(SimdLevels, SampleRowGivesTheReferencesBytesAlongAFieldsRows) {
  struct RowMap {
    const char* what;
    double x0, y0;   // frame coordinates of the row's first pixel
    double turnDeg;  // the row's direction in the frame
    double scale;    // frame pixels per field pixel (negative: mirrored)
    int nanAt = -1;  // a pixel whose coordinates are NaN
  };
  const RowMap maps[] = {
      {"level", 3.2, 40.6, 0.0, 1.0},
      {"turned 3 degrees", 3.7, 40.2, 3.0, 1.0},
      {"turned 4.5 degrees (blocks on two to four rows, all staged)", 3.1, 50.3, 4.5, 1.0},
      {"turned -6 degrees", 5.1, 120.9, -6.0, 0.97},
      {"turned 10 degrees (staged on up to five rows)", 2.3, 20.4, 10.0, 1.0},
      {"turned 30 degrees (a banked view)", 4.6, 30.2, 30.0, 1.0},
      {"turned -60 degrees", 150.3, 200.7, -60.0, 1.02},
      {"turned 90 degrees (down a frame column)", 100.4, 10.3, 90.0, 1.0},
      {"turned 100 degrees (leftwards and down)", 300.2, 12.9, 100.0, 0.98},
      {"turned 90 degrees, zoomed out 1.2 (climbing too far for a block: gathered)", 80.5, 5.5, 90.0, 1.2},
      {"zoomed out 1.3 (too wide for RGB: gathered)", 0.6, 60.1, 1.0, 1.3},
      {"zoomed out 4.5 (too wide for grey too)", 0.6, 60.1, 1.0, 4.5},
      {"zoomed in", 50.2, 70.7, 2.0, 0.6},
      {"mirrored", 355.4, 90.3, 2.0, -1.0},
      {"on the last rows", 1.4, 248.6, 0.5, 1.0},
      {"past the last row and the right edge", 300.5, 249.7, 1.0, 1.05},
      {"above the first row", -3.0, -0.8, 1.5, 1.0},
      {"with a NaN", 10.0, 30.0, 2.0, 1.0, 37},
  };
  const Image rgb = noiseImage(360, 250, PixelFormat::Rgb8, 77u), grey = noiseImage(360, 250, PixelFormat::Grey8, 78u);
  fieldcast::testing::atEverySimdLevel([&] {
    for (const RowMap& m : maps) {
      for (const Image* src : {&rgb, &grey}) {
        const int channels = src == &rgb ? 3 : 1;
        for (int n : {16, 64, 70}) {
          std::vector<float> xs(static_cast<std::size_t>(n)), ys(xs.size());
          const double c = std::cos(m.turnDeg * M_PI / 180.0), sn = std::sin(m.turnDeg * M_PI / 180.0);
          for (int i = 0; i < n; ++i) {
            xs[static_cast<std::size_t>(i)] = static_cast<float>(m.x0 + m.scale * c * i);
            ys[static_cast<std::size_t>(i)] = static_cast<float>(m.y0 + std::abs(m.scale) * sn * i);
          }
          if (m.nanAt >= 0 && m.nanAt < n)
            xs[static_cast<std::size_t>(m.nanAt)] = std::numeric_limits<float>::quiet_NaN();
          std::vector<std::uint8_t> fast(static_cast<std::size_t>(n * channels) + 1, 0xA5), ref = fast;
          const std::uint32_t vFast = sampleRow(*src, xs.data(), ys.data(), n, fast.data());
          const std::uint32_t vRef = sampleRowReference(*src, xs.data(), ys.data(), n, ref.data());
          ASSERT_EQ(fast, ref) << m.what << ", " << n << " pixels, " << channels << " channels";
          ASSERT_EQ(vFast, vRef) << m.what << ", " << n << " pixels, " << channels << " channels";
        }
      }
    }
  });
}

// The staged block itself (avx512vbmi), RGB and grey: taken for a field's blocks, level (two rows
// or three) or turned (climbing up to kMaxStagedRiseRows rows), and up to the frame's last bytes, which are followed by
// a page that may not be read; refused one pixel further on (its load would reach into that page), where the gathers
// take over.
TEST(SimdLevels, TheStagedSamplingTakesAFieldsBlocksAndStopsAtTheFramesLastByte) {
  if (!simdVbmiEnabled()) GTEST_SKIP() << "this CPU has no AVX-512 VBMI (level avx512vbmi)";
  // 16 samples from (x, y) on, `step` frame pixels apart, rising by `rise` pixels per sample and
  // bowed by `bow` · (i − 7.5)²
  const auto block = [&](const sampling::Source& src, int channels, float x, float y, float rise, bool staged,
                         float step = 1.0f, float bow = 0.0f) {
    float xs[16], ys[16];
    for (int i = 0; i < 16; ++i) {
      const float fromMiddle = static_cast<float>(i) - 7.5f;
      xs[i] = x + step * static_cast<float>(i);
      ys[i] = y + rise * static_cast<float>(i) + bow * fromMiddle * fromMiddle;
    }
    const auto bytes = static_cast<std::size_t>(16 * channels);
    std::vector<std::uint8_t> fast(bytes), ref(bytes), row(bytes);
    std::uint32_t violations = 0;
    EXPECT_EQ(sampling::sampleBlocksVbmi(src, channels, xs, ys, 16, fast.data(), violations) == 16, staged)
        << channels << " channels, block at " << x << ", " << y << " rising " << rise;
    const std::uint32_t refViolations = channels == 3 ? sampling::sampleRowScalar<3>(src, xs, ys, 16, ref.data())
                                                      : sampling::sampleRowScalar<1>(src, xs, ys, 16, ref.data());
    if (staged) {
      EXPECT_EQ(fast, ref) << channels << " channels, block at " << x << ", " << y;
      EXPECT_EQ(violations, refViolations);
    }
    // and the row as the kernel samples it at this level, staged or gathered
    forceSimdLevel("avx512vbmi");
    EXPECT_EQ(sampling::sampleRowLanes(src, channels, xs, ys, 16, row.data()), refViolations);
    EXPECT_EQ(row, ref);
    forceSimdLevel("auto");
  };
  withGuardedFrame(3, 64, 8, [&](const sampling::Source& src) {
    block(src, 3, 3.3f, 2.6f, 0.0f, true);    // two rows
    block(src, 3, 10.7f, 2.2f, 0.05f, true);  // three rows: the upper row changes within the block
    // On the last two rows: a load from x0 = 42 on row 6 ends two bytes before the frame's end
    block(src, 3, 42.6f, 6.7f, 0.0f, true);
    block(src, 3, 43.6f, 6.7f, 0.0f, false);       // one pixel on it would reach into the guard page
    block(src, 3, 3.3f, 2.6f, 0.2f, true);         // turned: upper rows 2 … 5, five rows staged
    block(src, 3, 3.3f, 2.6f, 0.0f, false, 1.3f);  // zoomed out: 20 pixels across
    // Where a row of the map turns back: the middle lanes' upper row 5, the ends' 4; three rows
    block(src, 3, 10.3f, 5.55f, 0.0f, true, 1.0f, -0.002f);
  });
  // Turned blocks climbing many rows: as a banked view's field rows do, and straight down a column
  withGuardedFrame(3, 64, 40, [&](const sampling::Source& src) {
    block(src, 3, 3.3f, 2.6f, 0.55f, true, 0.85f);          // rolled about 33°: upper rows 2 … 10
    block(src, 3, 3.3f, 2.6f, 1.0f, true, 0.0f);            // 90°: upper rows 2 … 17
    block(src, 3, 20.2f, 30.6f, -0.9f, true, 0.5f);         // climbing the other way: upper rows 30 down to 16
    block(src, 3, 3.3f, 2.6f, 16.0f / 15.0f, true, 0.0f);   // upper rows 2 … 18: the most a block may climb
    block(src, 3, 3.3f, 2.6f, 17.0f / 15.0f, false, 0.0f);  // 2 … 19: one row more
    // Down to the last row: the load from x0 = 42 on row 39 ends two bytes before the frame's end
    block(src, 3, 42.6f, 23.6f, 1.0f, true, 0.0f);
    block(src, 3, 43.6f, 23.6f, 1.0f, false, 0.0f);  // one pixel on it would reach into the guard page
    // Running past the last row: the lanes from y 39.5 on are clamped to upper row 38, weight 256
    // on row 39, and counted as violations from y 40 on
    block(src, 3, 3.3f, 30.6f, 1.0f, true, 0.0f);
  });
  withGuardedFrame(1, 100, 8, [&](const sampling::Source& src) {
    block(src, 1, 3.3f, 2.6f, 0.0f, true);
    block(src, 1, 10.7f, 2.2f, 0.05f, true);
    block(src, 1, 3.3f, 2.6f, 0.0f, true, 4.0f);   // zoomed out: 61 pixels across, still one load
    block(src, 1, 3.3f, 2.6f, 0.0f, false, 4.2f);  // 64: more than a load holds
    // On the last two rows: a load from x0 = 36 on row 6 ends at the frame's last byte
    block(src, 1, 36.6f, 6.7f, 0.0f, true);
    block(src, 1, 37.6f, 6.7f, 0.0f, false);  // one pixel on, its last byte would be the guard page's
    block(src, 1, 3.3f, 2.6f, 0.2f, true);    // turned: five rows
  });
  withGuardedFrame(1, 100, 40, [&](const sampling::Source& src) {
    block(src, 1, 3.3f, 2.6f, 1.0f, true, 0.0f);            // 90°: upper rows 2 … 17
    block(src, 1, 3.3f, 2.6f, 17.0f / 15.0f, false, 0.0f);  // 2 … 19: one row more than a block may climb
    block(src, 1, 36.6f, 23.6f, 1.0f, true, 0.0f);   // down to the last row: the load ends at the frame's last byte
    block(src, 1, 37.6f, 23.6f, 1.0f, false, 0.0f);  // one pixel on, its last byte would be the guard page's
  });
}

// Which runs of a field's rows are offered to the staged sampling at all: those whose blocks
// mostly fit it, a banked view's rows (turned by the roll) among them; the too wide and the too
// steep are gathered straight away.
TEST(SimdLevels, OnlyRowsWhoseBlocksMostlyFitAreOfferedToTheStagedSampling) {
  const auto run = [](double turnDeg, double scale, int n = 128) {
    std::vector<float> xs(static_cast<std::size_t>(n)), ys(xs.size());
    for (int i = 0; i < n; ++i) {
      xs[static_cast<std::size_t>(i)] = static_cast<float>(10.0 + scale * std::cos(turnDeg * M_PI / 180.0) * i);
      ys[static_cast<std::size_t>(i)] = static_cast<float>(40.0 + scale * std::sin(turnDeg * M_PI / 180.0) * i);
    }
    return std::pair{xs, ys};
  };
  const auto offered = [](int channels, const std::pair<std::vector<float>, std::vector<float>>& r) {
    return sampling::stagedBlocksLikelyFit(channels, r.first.data(), r.second.data(), static_cast<int>(r.first.size()));
  };
  EXPECT_TRUE(offered(3, run(0.0, 1.0)));
  EXPECT_TRUE(offered(3, run(3.0, 1.0)));     // 0.8 rows a block
  EXPECT_TRUE(offered(3, run(-5.0, 1.0)));    // 1.4
  EXPECT_TRUE(offered(3, run(6.0, 1.0)));     // 1.7: blocks on three or four rows
  EXPECT_TRUE(offered(3, run(-30.0, 1.0)));   // a banked turn: 8 rows a block
  EXPECT_TRUE(offered(3, run(80.0, 1.0)));    // 15.8
  EXPECT_FALSE(offered(3, run(90.0, 1.1)));   // 17.6 (a block 16.5): about half the blocks refused
  EXPECT_FALSE(offered(3, run(180.0, 1.3)));  // mirrored and zoomed out: 21 RGB pixels a block
  EXPECT_TRUE(offered(1, run(180.0, 1.3)));   // grey blocks may span 63
  EXPECT_FALSE(offered(1, run(0.0, 4.2)));
  EXPECT_TRUE(offered(3, run(30.0, 1.0, 31)));  // a short run: left to its blocks
  auto withNan = run(0.0, 1.0);
  withNan.second.back() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(offered(3, withNan));
}

TEST(SimdLevels, TheQuadraticsRowsAreTheScalarFormsFloats) {
  // Coefficients as a field's map has them (offset, slope, curvature), and extremes of each
  const float coefficients[][3] = {{31.7f, 1.013f, 2.9e-5f},   {2071.3f, -0.987f, -4.4e-5f}, {-40.0f, 1.3f, 5e-4f},
                                   {0.0f, 0.0f, 0.0f},         {1e6f, 123.5f, -0.75f},       {-3e-7f, 1e-9f, 7.0f},
                                   {5.5f, std::nanf(""), 0.0f}};
  fieldcast::testing::atEverySimdLevel([&] {
    std::vector<int> widths{128, 720, 1920};
    for (int n = 1; n <= 40; ++n) widths.push_back(n);
    for (const auto& k : coefficients) {
      for (const int n : widths) {
        std::vector<float> fast(static_cast<std::size_t>(n)), ref(fast.size());
        mapping::parabolaRowLanes(k[0], k[1], k[2], n, fast.data());
        mapping::parabolaRowScalar(k[0], k[1], k[2], 0, n, ref.data());
        ASSERT_EQ(std::memcmp(fast.data(), ref.data(), fast.size() * sizeof(float)), 0)
            << n << " pixels, coefficients " << k[0] << " " << k[1] << " " << k[2];
      }
    }
  });
}

// The largest distance (px) between a map's rows as the kernels work them out,
// rows(first, v, n, xs, ys), and the map itself, `exact`: every 7th row of a 1080i field, in the
// longest runs the kernels ask.
template <typename Rows, typename Map>
double largestRowError(Rows&& rows, const Map& exact) {
  double worst = 0.0;
  constexpr int n = mapping::kMaxRunPx;
  std::vector<float> xs(n), ys(n);
  for (int row = 0; row < 1080; row += 7) {
    const double v = row + 0.5;
    for (int first = 0; first < 1920; first += n) {
      rows(first, v, n, xs.data(), ys.data());
      for (int i = 0; i < n && first + i < 1920; ++i) {
        const glm::dvec2 p = exact({first + i + 0.5, v});
        const auto k = static_cast<std::size_t>(i);
        worst = std::max({worst, std::abs(xs[k] - p.x), std::abs(ys[k] - p.y)});
      }
    }
  }
  return worst;
}

TEST(SimdLevels, TheQuadraticsRowsAreWithinAThousandthOfAPixelOfTheMap) {
  // A 1080i field's map into a 2112 x 1188 frame (10 % margins): turned by 3°, zoomed by 2 %,
  // curved as a fast low pass makes it; every row's longest runs, as the kernels ask them
  const double c = 1.02 * std::cos(0.052), s = 1.02 * std::sin(0.052);
  QuadraticMap map;
  map.a = {96.0 + 28.0, c, -s, 2.1e-6, 3.7e-5, -1.9e-5};
  map.b = {54.0 - 41.0, s, c, -1.3e-6, 2.2e-5, 4.1e-5};
  fieldcast::testing::atEverySimdLevel([&] {
    const double worst = largestRowError(
        [&](int first, double v, int n, float* xs, float* ys) {
          mapping::quadraticRow(map.a, first, v, n, xs);
          mapping::quadraticRow(map.b, first, v, n, ys);
        },
        map);
    std::printf("largest error of the map's rows: %.2g px\n", worst);
    EXPECT_LT(worst, 1e-3);
  });
}

TEST(SimdLevels, TheHomographysRowsAreTheScalarFormsFloats) {
  // Lines as a field's map has them, one whose denominator turns negative along the run (the
  // horizon: NaN behind it), a NaN and a zero denominator
  const mapping::RatioRow rows[] = {{31.7f, 1.013f, 12.5f, 0.02f, 1.0f, 1e-4f},
                                    {2071.3f, -0.987f, 1100.0f, -0.03f, 0.97f, -2e-5f},
                                    {-40.0f, 1.3f, 8.0f, 0.9f, 0.02f, -1e-3f},
                                    {5.5f, std::nanf(""), 1.0f, 1.0f, 1.0f, 0.0f},
                                    {1.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f}};
  fieldcast::testing::atEverySimdLevel([&] {
    std::vector<int> widths{128, 256, 720};
    for (int n = 1; n <= 40; ++n) widths.push_back(n);
    for (const auto& r : rows) {
      for (const int n : widths) {
        const auto size = static_cast<std::size_t>(n);
        std::vector<float> fastX(size), fastY(size), refX(size), refY(size);
        mapping::ratioRowLanes(r, n, fastX.data(), fastY.data());
        mapping::ratioRowScalar(r, 0, n, refX.data(), refY.data());
        ASSERT_EQ(std::memcmp(fastX.data(), refX.data(), size * sizeof(float)), 0) << n << " pixels, " << r.ax;
        ASSERT_EQ(std::memcmp(fastY.data(), refY.data(), size * sizeof(float)), 0) << n << " pixels, " << r.ax;
      }
    }
    // The horizon row's pixels past w = 0 are NaN, those before it are not
    std::vector<float> xs(256), ys(256);
    mapping::ratioRowLanes(rows[2], 256, xs.data(), ys.data());
    EXPECT_FALSE(std::isnan(xs[0]));
    EXPECT_TRUE(std::isnan(xs[20]) && std::isnan(ys[20]));  // w = 0.02 − 0.0205 < 0
  });
}

TEST(SimdLevels, TheHomographysRowsAreWithinAThousandthOfAPixelOfTheMap) {
  // A 1080i field's homography into a 2112 x 1188 frame (10 % margins): turned by 3°, zoomed by
  // 2 %, seen from a camera that pitched and yawed a few degrees (the denominator varies from −2.6 % to +6 %)
  const double c = 1.02 * std::cos(0.052), s = 1.02 * std::sin(0.052);
  Homography h;
  h.h = {c, -s, 96.0 + 28.0, s, c, 54.0 - 41.0, 3.1e-5, -2.4e-5, 1.0};
  fieldcast::testing::atEverySimdLevel([&] {
    const double worst = largestRowError(
        [&](int first, double v, int n, float* xs, float* ys) { mapping::homographyRow(h.h, first, v, n, xs, ys); }, h);
    std::printf("largest error of the homography's rows: %.2g px\n", worst);
    EXPECT_LT(worst, 1e-3);
  });
}

TEST(SimdLevels, ConversionToUyvyWithGainGivesTheReferencesBytes) {
  fieldcast::testing::atEverySimdLevel([] {
    std::mt19937 rng(5);
    for (const int w : {2, 4, 6, 30, 34, 720}) {
      const Image src = noiseImage(w, 3, PixelFormat::Rgb8, static_cast<unsigned>(w));
      for (const std::int32_t gain :
           {65536, 32768, 4 * 65536, 65536 + 3277, 0, 128 << 16, 32768, static_cast<std::int32_t>(rng() % 262144u)}) {
        Image fast(w, 3, PixelFormat::Uyvy422), ref(w, 3, PixelFormat::Uyvy422);
        ASSERT_TRUE(convertPixels(src, fast, gain));
        ASSERT_TRUE(convertPixelsReference(src, ref, gain));
        ASSERT_TRUE(std::equal(fast.bytes().begin(), fast.bytes().end(), ref.bytes().begin()))
            << w << " pixels wide, gain " << gain;
      }
    }
  });
}

TEST(SimdLevels, TheAgcsMeanLumaIsTheReferences) {
  fieldcast::testing::atEverySimdLevel([] {
    // Every tail after a full block of every vector width (4, 8, 16 lanes), and real rows
    std::vector<int> widths{720, 1921};
    for (int w = 1; w <= 40; ++w) widths.push_back(w);
    for (const int w : widths) {
      for (const PixelFormat format : {PixelFormat::Rgb8, PixelFormat::Grey8}) {
        const Image src = noiseImage(w, 5, format, static_cast<unsigned>(w));
        for (const int step : {1, 2, 3}) {
          EXPECT_EQ(meanLuma(src, step), meanLumaReference(src, step)) << w << " pixels wide, step " << step;
        }
      }
    }
    // A field's rows all white: the brightest sums come out whole
    Image white(1921, 3, PixelFormat::Rgb8);
    std::fill(white.bytes().begin(), white.bytes().end(), std::uint8_t{255});
    EXPECT_EQ(meanLuma(white, 2), 255.0);
  });
}

TEST(SimdLevels, FlickerFilterGivesTheReferencesBytes) {
  fieldcast::testing::atEverySimdLevel([] {
    for (const PixelFormat format : {PixelFormat::Rgb8, PixelFormat::Grey8}) {
      for (const auto& [w, h] : {std::pair{1, 1}, std::pair{5, 2}, std::pair{37, 9}, std::pair{864, 7}}) {
        const Image src = noiseImage(w, h, format, static_cast<unsigned>(w + h));
        Image fast(w, h, format), ref(w, h, format);
        ASSERT_TRUE(flickerFilter(src, fast));
        ASSERT_TRUE(flickerFilterReference(src, ref));
        ASSERT_EQ(fast, ref) << w << "x" << h;
      }
    }
  });
}

// The lanes' filter takes two rounded means of bytes instead of the reference's sum: every one of
// the 2^24 (above, here, below) triples, at every level.
TEST(SimdLevels, FlickerFilterRowIsTheReferencesForEveryThreeBytes) {
  std::vector<std::uint8_t> above(65536), below(65536), here(65536), fast(65536), ref(65536);
  for (int k = 0; k < 65536; ++k) {
    above[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(k & 0xFF);
    below[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(k >> 8);
  }
  fieldcast::testing::atEverySimdLevel([&] {
    for (int b = 0; b < 256; ++b) {
      std::fill(here.begin(), here.end(), static_cast<std::uint8_t>(b));
      flicker::filterRowLanes(above.data(), here.data(), below.data(), 65536, fast.data());
      flicker::filterRowScalar(above.data(), here.data(), below.data(), 65536, ref.data());
      ASSERT_EQ(fast, ref) << "here " << b;
    }
  });
}

TEST(SimdLevels, AnUnknownLevelIsRefusedAndTheLevelStaysAsItWas) {
  const std::vector<std::string> levels = simdLevels();
  forceSimdLevel(levels.back());
  try {
    forceSimdLevel("avx1024");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(levels.back() + ", or auto"), std::string::npos) << e.what();
  }
  EXPECT_EQ(dispatchedSimdLevel(), levels.back());
  forceSimdLevel("auto");
  EXPECT_EQ(dispatchedSimdLevel(), levels.front());
}

}  // namespace
}  // namespace fieldcast::warp
