#pragma once
// Helpers shared by the terrain tests: scratch folders and small random grids.

#include <ig_core/TerrainBuilder.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fieldcast::core::testing {

/// A fresh folder under the test temp dir, removed with everything in it at destruction.
class ScratchDir {
 public:
  ScratchDir() {
    static std::atomic<int> counter{0};
    mPath = std::filesystem::path(::testing::TempDir()) /
            ("fieldcast-terrain-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1)));
    std::filesystem::remove_all(mPath);
    std::filesystem::create_directories(mPath);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(mPath, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return mPath; }
  std::filesystem::path operator/(const std::string& name) const { return mPath / name; }

 private:
  std::filesystem::path mPath;
};

/// A smooth-ish random grid (random walk rows) of `w`×`h` voxels.
inline TerrainGrid randomTerrainGrid(int w, int h, std::uint32_t seed) {
  TerrainGrid grid;
  grid.geometry.widthVox = w;
  grid.geometry.heightVox = h;
  grid.geometry.spacingM = 2.0;
  grid.geometry.originM = {1000.0, -500.0};
  grid.geometry.heightBaseM = -20.0;
  grid.geometry.heightStepM = 0.1;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> step(-30, 30);
  int value = 20000;
  for (int k = 0; k < w * h; ++k) {
    value = std::clamp(value + step(rng), 0, 65535);
    grid.heightQ.push_back(static_cast<std::uint16_t>(value));
    grid.colourRgba.push_back(static_cast<std::uint32_t>(rng()) | 0xFF000000u);
  }
  return grid;
}

/// Reads a whole file.
inline std::vector<char> readFile(const std::filesystem::path& path) {
  std::vector<char> bytes(static_cast<std::size_t>(std::filesystem::file_size(path)));
  std::ifstream in(path, std::ios::binary);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

/// Writes a whole file.
inline void writeFile(const std::filesystem::path& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace fieldcast::core::testing
