// MagicaVoxel .vox files: what is written reads back, more than 255 colours are reduced by median
// cut within a bound, chunks we do not use are skipped, damaged files are refused with the reason;
// a solid becomes sticks standing on the ground, and a placement list finds .vox models.
#include "TerrainTestUtil.h"

#include <ig_core/ModelLibrary.h>
#include <ig_core/VoxFile.h>

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fieldcast::core {
namespace {

using testing::ScratchDir;

std::uint32_t rgb(int r, int g, int b) {
  return static_cast<std::uint32_t>(r) | (static_cast<std::uint32_t>(g) << 8) | (static_cast<std::uint32_t>(b) << 16) |
         0xFF000000u;
}

// A 4 × 3 × 5 solid: a body of three colours on two wheels, a gap between them
VoxelSolid smallVan() {
  VoxelSolid s = emptySolid(4, 3, 5);
  for (int z = 2; z < 5; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) s.rgba[s.index(x, y, z)] = z == 4 ? rgb(200, 200, 210) : rgb(180, 30, 20 + 10 * x);
  for (int z = 0; z < 2; ++z)
    for (int x = 0; x < 4; ++x) {
      s.rgba[s.index(x, 0, z)] = rgb(20, 20, 20);
      s.rgba[s.index(x, 2, z)] = rgb(20, 20, 20);
    }
  return s;
}

std::vector<unsigned char> fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void expectRefused(const std::filesystem::path& path, const std::string& reason) {
  try {
    (void)readVoxFile(path);
    ADD_FAILURE() << "no error for a file that should say '" << reason << "'";
  } catch (const VoxFileError& e) {
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

TEST(VoxFile, ASolidOfFewColoursReadsBackExactly) {
  ScratchDir dir;
  const VoxelSolid van = smallVan();
  const VoxWriteReport report = writeVoxFile(dir.path() / "van.vox", van);
  EXPECT_EQ(report.paletteEntries, 6);
  EXPECT_EQ(report.maxColourError, 0);
  const VoxelSolid back = readVoxFile(dir.path() / "van.vox");
  EXPECT_EQ(back.sizeX, 4);
  EXPECT_EQ(back.sizeY, 3);
  EXPECT_EQ(back.sizeZ, 5);
  EXPECT_EQ(back.rgba, van.rgba);
  // The layout MagicaVoxel reads: header, MAIN, then SIZE's three sizes
  const std::vector<unsigned char> bytes = fileBytes(dir.path() / "van.vox");
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "VOX ");
  EXPECT_EQ(bytes[4], 150);
  EXPECT_EQ(std::string(bytes.begin() + 20, bytes.begin() + 24), "SIZE");
  EXPECT_EQ(bytes[32], 4);
  EXPECT_EQ(bytes[36], 3);
  EXPECT_EQ(bytes[40], 5);
}

TEST(VoxFile, MoreThan255ColoursAreReducedByMedianCutWithinABound) {
  ScratchDir dir;
  VoxelSolid s = emptySolid(32, 32, 1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) s.rgba[s.index(x, y, 0)] = rgb(x * 8, y * 8, (x + y) * 4);  // 1024 colours
  const VoxWriteReport report = writeVoxFile(dir.path() / "ramp.vox", s);
  EXPECT_EQ(report.paletteEntries, 255);
  EXPECT_GT(report.maxColourError, 0);
  EXPECT_LE(report.maxColourError, 16);
  const VoxelSolid back = readVoxFile(dir.path() / "ramp.vox");
  int worst = 0;
  for (std::size_t i = 0; i < s.rgba.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(static_cast<int>((s.rgba[i] >> (8 * c)) & 0xFF) -
                                       static_cast<int>((back.rgba[i] >> (8 * c)) & 0xFF)));
  EXPECT_EQ(worst, report.maxColourError);
  EXPECT_EQ(back.filledCount(), s.filledCount());
}

TEST(VoxFile, ChunksItDoesNotUseAreSkippedBySize) {
  ScratchDir dir;
  writeVoxFile(dir.path() / "van.vox", smallVan());
  std::vector<unsigned char> bytes = fileBytes(dir.path() / "van.vox");
  // A scene-graph node (nTRN, 8 content bytes) and a layer with a child, before SIZE
  const std::vector<unsigned char> extra{'n', 'T', 'R', 'N', 8,   0,   0,   0,   0,   0, 0, 0, 1, 2,  3,
                                         4,   5,   6,   7,   8,   'L', 'A', 'Y', 'R', 0, 0, 0, 0, 12, 0,
                                         0,   0,   'N', 'O', 'T', 'E', 0,   0,   0,   0, 0, 0, 0, 0};
  bytes.insert(bytes.begin() + 20, extra.begin(), extra.end());
  writeBytes(dir.path() / "scene.vox", bytes);
  EXPECT_EQ(readVoxFile(dir.path() / "scene.vox").rgba, smallVan().rgba);
}

TEST(VoxFile, DamagedFilesAreRefusedWithTheReason) {
  ScratchDir dir;
  writeVoxFile(dir.path() / "van.vox", smallVan());
  const std::vector<unsigned char> good = fileBytes(dir.path() / "van.vox");

  writeBytes(dir.path() / "cut.vox", {good.begin(), good.end() - 10});
  expectRefused(dir.path() / "cut.vox", "chunk RGBA runs past the end of the file");

  std::vector<unsigned char> outside = good;
  outside[60] = 9;  // XYZI at 44: the first voxel's x, beyond a size of 4
  writeBytes(dir.path() / "outside.vox", outside);
  expectRefused(dir.path() / "outside.vox", "voxel 0 at (9, ");

  std::vector<unsigned char> twoModels = good;
  twoModels.insert(twoModels.begin() + 20, good.begin() + 20, good.begin() + 44);  // a second SIZE
  writeBytes(dir.path() / "two.vox", twoModels);
  expectRefused(dir.path() / "two.vox", "several models");

  const std::size_t rgbaAt = good.size() - 1024 - 12;
  writeBytes(dir.path() / "nopalette.vox", {good.begin(), good.begin() + static_cast<std::ptrdiff_t>(rgbaAt)});
  expectRefused(dir.path() / "nopalette.vox", "no RGBA palette chunk");

  std::vector<unsigned char> huge = good;
  huge[32] = 0, huge[33] = 2;  // x size 512
  writeBytes(dir.path() / "huge.vox", huge);
  expectRefused(dir.path() / "huge.vox", "a model of 512 × 3 × 5 voxels (each side 1 … 256)");

  writeBytes(dir.path() / "text.vox", {'h', 'e', 'l', 'l', 'o'});
  expectRefused(dir.path() / "text.vox", "not a MagicaVoxel .vox file");
  expectRefused(dir.path() / "missing.vox", "cannot open");
  EXPECT_THROW(writeVoxFile(dir.path() / "big.vox", emptySolid(300, 2, 2)), VoxFileError);
}

TEST(VoxelSolidToSticks, AColumnOverAGapIsAComplexStickWithACavity) {
  const VoxelModel model = toVoxelModel(smallVan(), "van");
  EXPECT_EQ(model.widthCells, 4);
  EXPECT_EQ(model.depthCells, 3);
  EXPECT_DOUBLE_EQ(model.cellM, kSolidVoxelM);
  // The middle row (y = 1) has the body over a gap: five texels, the lower two a cavity
  const VoxelModel::Column& middle = model.columns[static_cast<std::size_t>(1 * 4 + 2)];
  ASSERT_GT(middle.stick, 0u);
  EXPECT_EQ(middle.heightUnits, 5);
  const StickEntry& entry = model.sticks[middle.stick - 1];
  EXPECT_EQ(entry.kind, StickKind::Complex);
  ASSERT_EQ(entry.texels.size(), 5u);
  EXPECT_EQ(entry.texels[0], rgb(200, 200, 210));
  EXPECT_EQ(entry.texels[1], rgb(180, 30, 40));
  EXPECT_EQ(entry.texels[3], kCavityRgba);
  EXPECT_EQ(entry.texels[4], kCavityRgba);
  // Over the wheels no gap: textured
  EXPECT_EQ(model.sticks[model.columns[2].stick - 1].kind, StickKind::Textured);
  // The wheel rows (y = 0 and 2) of one x are the same column: one stick for both
  EXPECT_EQ(model.columns[2].stick, model.columns[static_cast<std::size_t>(2 * 4 + 2)].stick);
  EXPECT_EQ(model.sticks.size(), 8u);  // 4 colours of x, each over a gap and over wheels
}

TEST(VoxelSolidToSticks, OneColourIsAUniformStickAndEmptyColumnsStayEmpty) {
  VoxelSolid s = emptySolid(2, 1, 3);
  for (int z = 0; z < 3; ++z) s.rgba[s.index(0, 0, z)] = rgb(10, 200, 10);
  const VoxelModel model = toVoxelModel(s, "post");
  ASSERT_EQ(model.sticks.size(), 1u);
  EXPECT_EQ(model.sticks[0].kind, StickKind::Uniform);
  EXPECT_EQ(model.columns[0].heightUnits, 3);
  EXPECT_EQ(model.columns[1].stick, 0u);
  EXPECT_THROW(toVoxelModel(emptySolid(2, 2, 2), "nothing"), std::invalid_argument);
}

TEST(ModelLibrary, FindsBuiltInModelsAndVoxFilesBesideTheListOnce) {
  ScratchDir dir;
  writeVoxFile(dir.path() / "van.vox", smallVan());
  ModelLibrary library(dir.path());
  EXPECT_EQ(library.find("house"), findBuiltinModel("house"));
  const VoxelModel* van = library.find("van.vox");
  ASSERT_NE(van, nullptr);
  EXPECT_EQ(van->widthCells, 4);
  EXPECT_EQ(library.find("van.vox"), van);
  EXPECT_EQ(library.find("castle"), nullptr);
  EXPECT_THROW(library.find("lorry.vox"), VoxFileError);
}

}  // namespace
}  // namespace fieldcast::core
