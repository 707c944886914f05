// fieldcast_bench_table: the column caster's frame time next to two independent renderers of the
// same terrain and camera, and the service's field step next to cv::remap, printed as the Markdown
// tables of the README's "Speed" section:
//
//   fieldcast_bench_table [--cache-dir=DIR] [--rounds=N] [--sizes=ntsc,hd] [--threads=1,2]
//                         [--frames=DIR]   (also writes each view's three pictures there, as PPM)
//
// For each bench view (BenchPoses.h) × display size × thread count: Fieldcast's caster at full
// sharpness (quality 1, grazing rule off), an Embree 3 primary-ray render of level 0
// (EmbreeHeightField.h), and a VoxelSpace-style column render (VoxelSpaceRenderer.h, low and
// horizon views only: its pitch is a shear). Each round renders one frame with each, in turn, so
// that all three see the same machine load; the table gives the medians over the rounds and the
// ratios to Fieldcast's. Frames include the margins (10% a side). "Same surface" is the share of
// pixels where the caster's range image and Embree's agree (agreement() below), once per view. The built-in terrain is
// generated into the cache folder on first use.
//
// Then the field warp on one core at every SIMD level this CPU runs, NTSC and 1080i fields: the
// service's whole field step (pose, fit, warp of the flicker-filtered frame, AGC, UYVY; a new frame every field,
// with its flicker-filtered copy as the render loop hands it over)
// against cv::remap doing the same warp with its map built per field (RGB, OpenCV on one thread),
// alternated the same way (WarpSetup.h: the cases of fieldcast_bench_warp).
#include "BenchPoses.h"
#include "EmbreeHeightField.h"
#include "LevelZeroGrid.h"
#include "VoxelSpaceRenderer.h"
#include "WarpSetup.h"

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/OpenTerrain.h>
#include <ig_core/Renderer.h>
#include <ig_core/TileCache.h>
#include <ig_core/ViewGeometry.h>

#include <fieldcast/SimdLevel.h>

#include <opencv2/core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::core {
namespace {

struct Options {
  std::string cacheDir;
  int rounds = 9;
  std::vector<int> sizes{0, 1};
  std::vector<int> threads{1, 2};
  std::string framesDir;
};

std::vector<int> parseList(const std::string& text, const std::function<int(const std::string&)>& item) {
  std::vector<int> out;
  std::stringstream in(text);
  for (std::string word; std::getline(in, word, ',');) out.push_back(item(word));
  return out;
}

Options parseOptions(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto value = [&](const std::string& key) { return arg.rfind(key, 0) == 0 ? arg.substr(key.size()) : ""; };
    if (arg.rfind("--cache-dir=", 0) == 0) {
      o.cacheDir = value("--cache-dir=");
    } else if (arg.rfind("--rounds=", 0) == 0) {
      o.rounds = std::max(1, std::stoi(value("--rounds=")));
    } else if (arg.rfind("--sizes=", 0) == 0) {
      o.sizes = parseList(value("--sizes="), [](const std::string& s) {
        if (s == "ntsc") return 0;
        if (s == "hd") return 1;
        throw std::invalid_argument("--sizes: '" + s + "' is neither ntsc nor hd");
      });
    } else if (arg.rfind("--frames=", 0) == 0) {
      o.framesDir = value("--frames=");
    } else if (arg.rfind("--threads=", 0) == 0) {
      o.threads = parseList(value("--threads="), [](const std::string& s) { return std::max(1, std::stoi(s)); });
    } else {
      throw std::invalid_argument("unknown argument '" + arg +
                                  "' (--cache-dir=DIR, --rounds=N, --sizes=ntsc,hd, --threads=1,2, --frames=DIR)");
    }
  }
  return o;
}

// A binary PPM of `rgb` (width × height × 3 bytes, rows top down)
void writePpm(const std::filesystem::path& path, int width, int height, const std::uint8_t* rgb) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) throw std::runtime_error(path.string() + ": cannot write");
  std::fprintf(file, "P6\n%d %d\n255\n", width, height);
  const bool written =
      std::fwrite(rgb, 3, static_cast<std::size_t>(width) * height, file) == static_cast<std::size_t>(width) * height;
  if (std::fclose(file) != 0 || !written) throw std::runtime_error(path.string() + ": cannot write");
}

// Pixels where the caster and Embree see the same thing: both the sky, or the terrain at ranges
// within 2% of each other (objects are sticks to the caster, bumps of the height field to Embree)
double agreement(const std::vector<float>& ours, const std::vector<float>& theirs) {
  std::size_t same = 0;
  for (std::size_t k = 0; k < ours.size(); ++k) {
    const bool sky = !std::isfinite(ours[k]), theirSky = !std::isfinite(theirs[k]);
    same += sky || theirSky ? sky == theirSky : std::abs(ours[k] - theirs[k]) <= 0.02f * ours[k];
  }
  return static_cast<double>(same) / static_cast<double>(ours.size());
}

double secondsOf(const auto& render) {
  const auto start = std::chrono::steady_clock::now();
  render();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double medianMs(std::vector<double> seconds) {
  std::sort(seconds.begin(), seconds.end());
  return 1e3 * seconds[seconds.size() / 2];
}

// Mean seconds per call of `fn` over `calls` calls
double meanSeconds(int calls, const auto& fn) {
  return secondsOf([&] {
           for (int k = 0; k < calls; ++k) fn();
         }) /
         calls;
}

void printWarpTable(int rounds) {
  cv::setNumThreads(1);  // one core each
  std::printf(
      "\nThe field warp, one core: the service's field step (pose, fit, warp of the flicker-filtered frame, AGC, "
      "UYVY; a new frame every field, with the filtered copy the render loop makes) against cv::remap with its map "
      "built per field (RGB), %d alternated "
      "rounds of 50 fields, medians.\n\n",
      rounds);
  std::printf("| field | SIMD level | field step ms | cv::remap ms | cv::remap / field step |\n");
  std::printf("| --- | --- | ---: | ---: | ---: |\n");
  for (const int raster : {0, 1}) {
    const warp::Setup& s = warp::setup(raster);
    for (const std::string& level : simdLevels()) {
      const warp::AtLevel at(level);
      warp::FieldStep step(s, true);
      warp::RemapPerField remap(s);
      std::vector<double> ours, theirs;
      meanSeconds(10, [&] { step.run(); });  // warm-up
      meanSeconds(10, [&] { remap.run(true); });
      for (int round = 0; round < rounds; ++round) {
        ours.push_back(meanSeconds(50, [&] { step.run(); }));
        theirs.push_back(meanSeconds(50, [&] { remap.run(true); }));
      }
      const double oursMs = medianMs(ours), theirsMs = medianMs(theirs);
      std::printf("| %d × %d | %s | %.2f | %.2f | %.2f × |\n", s.rasterW, fieldRowCount(FieldParity::Bottom, s.rasterH),
                  level.c_str(), oursMs, theirsMs, theirsMs / oursMs);
      std::fflush(stdout);
    }
  }
}

int run(const Options& options) {
  const std::filesystem::path cacheDir =
      options.cacheDir.empty() ? defaultCacheDir() : std::filesystem::path(options.cacheDir);
  const std::unique_ptr<TileCache> cache = openTerrain("builtin", cacheDir, std::size_t{3} << 30);
  const TerrainView& view = cache->view();
  std::fprintf(stderr, "reading level 0 for Embree and VoxelSpace ...\n");
  const LevelZeroGrid grid = readLevelZero(builtinDatabasePath(cacheDir, BuiltinTerrainSpec{}));
  std::fprintf(stderr, "building the Embree scene ...\n");
  const auto buildStart = std::chrono::steady_clock::now();
  const EmbreeHeightField embree(grid);
  const double buildS = std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();

  RenderSettings settings;  // full sharpness: quality 1, the grazing-angle rule off
  settings.quality = 1.0;
  settings.maxAnisotropy = 0.0;
  std::printf("Built-in terrain %d² voxels at %.0f m; Embree scene built in %.1f s; %d alternated rounds, medians.\n",
              grid.geometry.widthVox, grid.geometry.spacingM, buildS, options.rounds);
  std::printf("The caster has no run-time dispatched kernels yet (the warp's level here: %s).\n\n",
              simdLevel().c_str());
  std::printf(
      "| view | frame (with margins) | threads | Fieldcast ms | Embree ms | Embree / Fieldcast | "
      "VoxelSpace ms | VoxelSpace / Fieldcast | same surface as Embree |\n");
  std::printf("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  std::vector<std::uint8_t> rgb;
  for (const int size : options.sizes) {
    for (int pose = 0; pose < static_cast<int>(kPoses.size()); ++pose) {
      const ViewRequest request = benchRequest(view, pose, size);
      const FrameLayout layout = layoutFrame(request.display, settings.marginFraction, 0.0);
      cache->prefetch(request.pose, glm::dvec3{0.0}, layout.frame, prefetchLod(settings));
      cache->waitIdle(std::chrono::seconds(120));
      const FrameLease lease = cache->lease();
      const ViewGeometry geometry(request.pose, layout.frame, view.geometry(), settings);
      const bool voxelSpace = kPoses[static_cast<std::size_t>(pose)].nearHorizon;
      // The same surface? Both frames' ranges, compared once per view (outside the timed rounds)
      RenderSettings withRange = settings;
      withRange.rangeImage = true;
      const Frame ranged = Renderer(view, withRange, 2).render(request);
      std::vector<float> embreeRange;
      embree.render(geometry, 2, rgb, &embreeRange);
      const double same = agreement(ranged.rangeM, embreeRange);
      for (const int threads : options.threads) {
        Renderer renderer(view, settings, threads);
        Frame frame = renderer.render(request);  // warm-up, each
        embree.render(geometry, threads, rgb);
        std::vector<double> ours, theirs, columns;
        for (int round = 0; round < options.rounds; ++round) {
          ours.push_back(secondsOf([&] { frame = renderer.render(request, nullptr, std::move(frame)); }));
          theirs.push_back(secondsOf([&] { embree.render(geometry, threads, rgb); }));
          if (voxelSpace) columns.push_back(secondsOf([&] { renderVoxelSpace(grid, geometry, threads, rgb); }));
        }
        if (!options.framesDir.empty() && threads == options.threads.front()) {
          const std::string name = std::string(kPoses[static_cast<std::size_t>(pose)].name) + "-" +
                                   std::to_string(layout.frame.widthPx) + "-";
          const std::filesystem::path dir = options.framesDir;
          std::filesystem::create_directories(dir);
          writePpm(dir / (name + "fieldcast.ppm"), frame.image.widthPx(), frame.image.heightPx(),
                   frame.image.bytes().data());
          embree.render(geometry, threads, rgb);
          writePpm(dir / (name + "embree.ppm"), layout.frame.widthPx, layout.frame.heightPx, rgb.data());
          if (voxelSpace) {
            renderVoxelSpace(grid, geometry, threads, rgb);
            writePpm(dir / (name + "voxelspace.ppm"), layout.frame.widthPx, layout.frame.heightPx, rgb.data());
          }
        }
        const double oursMs = medianMs(ours), theirsMs = medianMs(theirs);
        std::printf("| %s | %d × %d | %d | %.2f | %.1f | %.1f × |", kPoses[static_cast<std::size_t>(pose)].name,
                    layout.frame.widthPx, layout.frame.heightPx, threads, oursMs, theirsMs, theirsMs / oursMs);
        if (voxelSpace) {
          const double columnsMs = medianMs(columns);
          std::printf(" %.2f | %.2f × |", columnsMs, columnsMs / oursMs);
        } else {
          std::printf(" — | — |");
        }
        std::printf(" %.1f%% |\n", 100.0 * same);
        std::fflush(stdout);
      }
    }
  }
  printWarpTable(options.rounds);
  return 0;
}

}  // namespace
}  // namespace fieldcast::core

int main(int argc, char** argv) {
  try {
    return fieldcast::core::run(fieldcast::core::parseOptions(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast_bench_table: %s\n", e.what());
    return 1;
  }
}
