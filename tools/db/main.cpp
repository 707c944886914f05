// fieldcast-db: the terrain database tool.
//   fieldcast-db build --builtin [--size N --seed S --spacing M] -o out.fctdb
//   fieldcast-db build --dem elevation.tif [--ortho photo.jpg] [--objects placements.csv] -o out.fctdb
//   fieldcast-db info db.fctdb          header, georeference, levels, sizes, compression, height ranges
//   fieldcast-db verify db.fctdb        reads and checks every tile; exit 1 on any failure
//   fieldcast-db preview db.fctdb -o level.png [--level L] [--shaded]
//   fieldcast-db landmarks [--size N --seed S --spacing M]
#include <tools/OptionChecks.h>

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/ElevationImport.h>
#include <ig_core/Georeference.h>
#include <ig_core/ModelLibrary.h>
#include <ig_core/ObjectPlacement.h>
#include <ig_core/TerrainBuilder.h>
#include <ig_core/TerrainDatabase.h>

#include <OpenImageIO/imageio.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace fieldcast::core;
using namespace fieldcast::tools;

struct BuildArgs {
  bool builtin = false;
  std::string dem;
  std::string ortho;
  std::string objects;         ///< placement list (CSV), empty: none
  bool builtinObjects = true;  ///< the built-in terrain furnished
  std::string output;
  int size = 8192;
  double spacing = 2.0;
  std::uint64_t seed = 1;
  int tileShift = 8;
  bool grey = false;
  int threads = 0;
  int zstdLevel = 3;
  double sunAzimuth = 315.0;
  double sunElevation = 40.0;
  double demSpacing = 0.0;
  std::optional<double> nodata;
  std::string rawSize;
  std::string rawType = "int16";
  double verticalScale = 1.0;
  double verticalOffset = 0.0;
};

// Ranges of the numeric options. Spacing: 1 cm (a lidar survey) to 100 km; a DEM in geographic
// degrees (0.0003) is refused rather than built as a postage stamp.
constexpr double kMinSpacingM = 0.01;
constexpr double kMaxSpacingM = 100'000.0;
constexpr int kMinBuiltinSizeVox = 64;
constexpr int kMaxBuiltinSizeVox = 32768;
constexpr double kMaxVerticalScaleM = 1000.0;
constexpr double kMinVerticalScaleM = 1e-6;
constexpr double kMaxVerticalOffsetM = 100'000.0;

/// Refuses an output that cannot be written before any work is done: the folder must exist and
/// be writable, and the name must not be a folder. (The database itself is written atomically.)
void checkOutputWritable(const std::string& output) {
  namespace fs = std::filesystem;
  const fs::path path(output);
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw std::invalid_argument("-o " + output + ": is a folder; expected a file name");
  if (!fs::exists(folder, ec))
    throw std::invalid_argument("-o " + output + ": folder " + folder.string() + " does not exist");
  if (!fs::is_directory(folder, ec)) {
    throw std::invalid_argument("-o " + output + ": " + folder.string() + " is not a folder");
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw std::invalid_argument("-o " + output + ": cannot write in " + folder.string() + ": " + std::strerror(errno));
  }
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

int runBuild(const BuildArgs& a) {
  checkOutputWritable(a.output);  // before the import, which can take minutes
  const auto start = std::chrono::steady_clock::now();
  ConsoleProgress console(a.builtin ? "built-in terrain" : a.dem);
  ProceduralColourOptions colour;
  colour.sunAzimuthDeg = a.sunAzimuth;
  colour.sunElevationDeg = a.sunElevation;
  colour.output = a.grey ? ColourOutput::Grey : ColourOutput::Colour;
  colour.threads = a.threads;
  TerrainGrid grid;
  if (a.builtin) {
    BuiltinTerrainSpec spec;
    spec.sizeVox = a.size;
    spec.spacingM = a.spacing;
    spec.seed = a.seed;
    spec.objects = a.builtinObjects;
    grid = generateBuiltinTerrain(spec, colour, console.callback());
  } else {
    ImportOptions import;
    import.spacingM = a.demSpacing;
    import.nodata = a.nodata;
    if (!a.rawSize.empty()) {
      int used = 0;
      if (std::sscanf(a.rawSize.c_str(), "%dx%d%n", &import.rawWidth, &import.rawHeight, &used) != 2 ||
          static_cast<std::size_t>(used) != a.rawSize.size() || import.rawWidth < 1 || import.rawHeight < 1 ||
          import.rawWidth > kMaxDatabaseSideVox || import.rawHeight > kMaxDatabaseSideVox) {
        throw std::invalid_argument("--raw-size: expected WxH with W and H from 1 to " +
                                    std::to_string(kMaxDatabaseSideVox) + " voxels, got '" + a.rawSize + "'");
      }
    }
    import.rawType = a.rawType;
    import.verticalScaleM = a.verticalScale;
    import.verticalOffsetM = a.verticalOffset;
    const ElevationGrid dem = importElevation(a.dem, import);
    if (!(dem.spacingM >= kMinSpacingM && dem.spacingM <= kMaxSpacingM)) {
      throw std::invalid_argument(a.dem + ": voxel spacing " + formatNumber(dem.spacingM) +
                                  (dem.spacingFromFile ? " m (from the file)" : " m") + ": expected " +
                                  formatNumber(kMinSpacingM) + " to " + formatNumber(kMaxSpacingM) +
                                  " m (a DEM in geographic degrees? give --dem-spacing in metres)");
    }
    std::printf("%s: %dx%d voxels, spacing %.3f m, origin (%.1f, %.1f), heights %.2f .. %.2f m, %zu nodata filled\n",
                a.dem.c_str(), dem.widthVox, dem.heightVox, dem.spacingM, dem.originM.x, dem.originM.y, dem.minM,
                dem.maxM, dem.nodataFilled);
    std::printf(
        "%s: georeference %s\n", a.dem.c_str(),
        dem.crs.empty() ? "none (the file gives no CRS)" : Georeference::fromCrs(dem.crs).description().c_str());
    grid = quantiseElevation(dem);
    if (!a.ortho.empty()) {
      OrthophotoPlacement placement;
      grid.colourRgba = drapeOrthophoto(a.ortho, grid.geometry, placement, colour.output, 0xFF808080u, a.threads);
    } else {
      grid.colourRgba = bakeProceduralColour(grid.geometry, grid.heightQ, {}, colour);
    }
  }
  if (!a.objects.empty()) {
    const std::vector<ObjectPlacement> objects = readPlacementList(a.objects);
    ModelLibrary models(std::filesystem::path(a.objects).parent_path());
    const PlacementReport placed = placeObjects(grid, objects, models.lookup(), a.threads);
    std::printf("%s: %zu objects placed (%zu off the grid), %zu voxels with sticks, %u stick table entries\n",
                a.objects.c_str(), placed.placed, placed.offGrid, placed.stickVoxels, placed.tableEntries);
  }
  BuildOptions options;
  options.tileShift = a.tileShift;
  options.voxelColour = a.grey ? VoxelColour::Grey : VoxelColour::Rgba;
  options.threads = a.threads;
  options.zstdLevel = a.zstdLevel;
  options.progress = console.callback();
  const BuildReport report = writeTerrainDatabase(grid, a.output, options);
  std::printf("%s: %dx%d voxels, %d levels, %llu tiles, %.1f MiB (%.2fx smaller than raw) in %.1f s\n",
              a.output.c_str(), report.geometry.widthVox, report.geometry.heightVox, report.geometry.levels,
              static_cast<unsigned long long>(report.tileCount), static_cast<double>(report.fileBytes) / 1048576.0,
              static_cast<double>(report.rawBytes) / static_cast<double>(report.fileBytes), seconds(start));
  return 0;
}

/// The lowest and highest height code stored at level 0, over the voxels inside the grid (tiles
/// past the edge repeat the edge voxel, so they add nothing). The header holds only the
/// quantisation, so this reads and decodes every level-0 tile.
struct StoredHeightRange {
  std::uint16_t minQ = 0xFFFF;
  std::uint16_t maxQ = 0;
  std::uint64_t tilesRead = 0;
  std::uint64_t tilesBad = 0;     ///< unreadable tiles, left out of the range (verify names them)
  std::uint64_t stickVoxels = 0;  ///< level-0 voxels inside the grid that carry a stick
};

StoredHeightRange scanLevel0Heights(const DatabaseReader& reader) {
  const TerrainGeometry& g = reader.geometry();
  const int side = g.tileSizeVox();
  StoredHeightRange r;
  TileBuffers tile;
  for (int ty = 0; ty < g.tilesY(0); ++ty) {
    for (int tx = 0; tx < g.tilesX(0); ++tx) {
      try {
        reader.readTile(0, tx, ty, tile);
      } catch (const TerrainDatabaseError&) {
        ++r.tilesBad;
        continue;
      }
      ++r.tilesRead;
      const int rows = std::min(side, g.heightVox - ty * side);
      const int columns = std::min(side, g.widthVox - tx * side);
      for (int y = 0; y < rows; ++y) {
        const std::uint16_t* row = tile.heightQ.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(side);
        const auto [lo, hi] = std::minmax_element(row, row + columns);
        r.minQ = std::min(r.minQ, *lo);
        r.maxQ = std::max(r.maxQ, *hi);
        if (!tile.stickId.empty()) {
          const std::uint32_t* ids = tile.stickId.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(side);
          r.stickVoxels +=
              static_cast<std::uint64_t>(std::count_if(ids, ids + columns, [](auto id) { return id != 0; }));
        }
      }
    }
  }
  return r;
}

/// The CRS and where the grid's corner voxels lie on the Earth; or how a database without a CRS is
/// placed (the tangent plane the host link uses).
void printGeoreference(const DatabaseLayout& l) {
  const TerrainGeometry& g = l.geometry;
  if (l.crs.empty()) {
    std::printf("  georef      none (%s); latitude/longitude map onto the %s, world (0, 0) there\n",
                l.version < 2 ? "a version 1 database" : "no CRS", Georeference::tangentPlane().description().c_str());
    return;
  }
  try {
    const Georeference geo = Georeference::fromCrs(l.crs);
    std::printf("  georef      %s: world x, y are its easting and northing\n", geo.description().c_str());
    std::printf("  crs         %s\n", l.crs.c_str());
    const auto corner = [&](int i, int j) {
      const glm::dvec3 world(g.originM.x + i * g.spacingM, g.originM.y + j * g.spacingM, 0.0);
      const std::optional<GeodeticPosition> p = geo.toGeodetic(world);
      char text[64] = "outside the CRS's domain";
      if (p) {
        std::snprintf(text, sizeof text, "%.6f %s, %.6f %s", std::fabs(p->latitudeDeg), p->latitudeDeg < 0 ? "S" : "N",
                      std::fabs(p->longitudeDeg), p->longitudeDeg < 0 ? "W" : "E");
      }
      return std::string(text);
    };
    std::printf("  corners     voxel centres: south-west %s, north-east %s (WGS 84)\n", corner(0, 0).c_str(),
                corner(g.widthVox - 1, g.heightVox - 1).c_str());
  } catch (const GeoreferenceError& e) {
    std::printf("  georef      unusable: %s\n  crs         %s\n", e.what(), l.crs.c_str());
  }
}

int runInfo(const std::string& path) {
  const DatabaseReader reader(path);
  const DatabaseLayout& l = reader.layout();
  const TerrainGeometry& g = l.geometry;
  const StoredHeightRange stored = scanLevel0Heights(reader);
  std::printf("%s: Fieldcast terrain database, version %u\n", path.c_str(), l.version);
  std::printf("  grid        %d x %d voxels, spacing %.3f m (%.1f x %.1f km)\n", g.widthVox, g.heightVox, g.spacingM,
              g.widthVox * g.spacingM / 1000.0, g.heightVox * g.spacingM / 1000.0);
  std::printf("  origin      voxel (0,0) centre at x %.3f, y %.3f m\n", g.originM.x, g.originM.y);
  printGeoreference(l);
  if (stored.tilesRead > 0) {
    std::printf("  heights     data %.2f .. %.2f m (lowest and highest voxel, from all %llu level-0 tiles%s)\n",
                g.heightM(stored.minQ), g.heightM(stored.maxQ), static_cast<unsigned long long>(stored.tilesRead),
                stored.tilesBad > 0 ? ", unreadable tiles left out: run verify" : "");
  } else {
    std::printf("  heights     data unknown: no level-0 tile could be read (run verify)\n");
  }
  if (stored.tilesBad > 0) {
    std::printf("              %llu level-0 tiles unreadable\n", static_cast<unsigned long long>(stored.tilesBad));
  }
  std::printf("  quantised   z = %.3f + %.4f * q, q 0..65535: can hold %.2f .. %.2f m\n", g.heightBaseM, g.heightStepM,
              g.heightBaseM, g.heightM(65535));
  std::printf("  colour      %s\n", l.voxelColour == VoxelColour::Rgba ? "RGBA" : "grey");
  if (const auto& sticks = reader.sticks()) {
    std::uint64_t uniform = 0, complex = 0;
    for (std::uint32_t id = 1; id <= sticks->size(); ++id) {
      uniform += sticks->entry(id).kind == StickKind::Uniform;
      complex += sticks->entry(id).kind == StickKind::Complex;
    }
    std::printf(
        "  sticks      %llu level-0 voxels carry one; table of %u entries (%llu uniform, %llu textured, %llu complex), "
        "%.1f KiB, stick voxels %.2f m\n",
        static_cast<unsigned long long>(stored.stickVoxels), sticks->size(), static_cast<unsigned long long>(uniform),
        static_cast<unsigned long long>(sticks->size() - uniform - complex), static_cast<unsigned long long>(complex),
        l.stickTableBytes / 1024.0, sticks->unitM());
  } else {
    std::printf("  sticks      none%s\n", l.version < 3 ? " (a version 1 or 2 database)" : "");
  }
  std::printf("  tiles       %d x %d voxels, %llu tiles over %d levels\n", g.tileSizeVox(), g.tileSizeVox(),
              static_cast<unsigned long long>(l.tileCount), g.levels);
  for (int level = 0; level < g.levels; ++level) {
    std::printf("    level %2d  %6d x %-6d voxels  %4d x %-4d tiles\n", level, g.levelWidthVox(level),
                g.levelHeightVox(level), g.tilesX(level), g.tilesY(level));
  }
  const double raw =
      static_cast<double>(l.tileCount) * static_cast<double>(rawTileBytes(g.tileShift, l.voxelColour, l.version >= 3));
  std::printf("  size        %.1f MiB on disk, %.1f MiB of tiles uncompressed (%.2fx)\n",
              static_cast<double>(l.fileBytes) / 1048576.0, raw / 1048576.0,
              raw / static_cast<double>(reader.compressedBytes()));
  return 0;
}

int runVerify(const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  const DatabaseReader reader(path);
  const TerrainGeometry& g = reader.geometry();
  TileBuffers tile;
  std::uint64_t bad = 0, good = 0, stickVoxels = 0;
  for (int level = 0; level < g.levels; ++level) {
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) {
        try {
          reader.readTile(level, tx, ty, tile);  // checks every stick id against the table
          ++good;
          if (level == 0)
            stickVoxels += static_cast<std::uint64_t>(
                std::count_if(tile.stickId.begin(), tile.stickId.end(), [](auto id) { return id != 0; }));
        } catch (const TerrainDatabaseError& e) {
          std::fprintf(stderr, "%s\n", e.what());
          ++bad;
        }
      }
    }
  }
  std::printf("%s: %llu tiles good, %llu bad (%.1f s)\n", path.c_str(), static_cast<unsigned long long>(good),
              static_cast<unsigned long long>(bad), seconds(start));
  if (const auto& sticks = reader.sticks()) {
    std::printf(
        "%s: stick table of %u entries read and checked; every stick id of the good tiles lies in it "
        "(%llu in level-0 tiles, edge repeats included)\n",
        path.c_str(), sticks->size(), static_cast<unsigned long long>(stickVoxels));
  }
  return bad == 0 ? 0 : 1;
}

int runPreview(const std::string& path, const std::string& output, int level, bool heights) {
  const DatabaseReader reader(path);
  const TerrainGeometry& g = reader.geometry();
  if (level < 0) {
    level = 0;
    while (level < g.levels - 1 && std::max(g.levelWidthVox(level), g.levelHeightVox(level)) > 2048) ++level;
  }
  if (level >= g.levels)
    throw std::invalid_argument("--level: the database has levels 0.." + std::to_string(g.levels - 1));
  const int w = g.levelWidthVox(level);
  const int h = g.levelHeightVox(level);
  const int side = g.tileSizeVox();
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  TileBuffers tile;
  for (int ty = 0; ty < g.tilesY(level); ++ty) {
    for (int tx = 0; tx < g.tilesX(level); ++tx) {
      reader.readTile(level, tx, ty, tile);
      for (int y = 0; y < side; ++y) {
        const int j = ty * side + y;
        if (j >= h) break;
        for (int x = 0; x < side; ++x) {
          const int i = tx * side + x;
          if (i >= w) break;
          const std::size_t k = static_cast<std::size_t>(y) * side + x;
          // Image rows run top (north) to bottom; grid rows run south to north.
          std::uint8_t* p = pixels.data() + (static_cast<std::size_t>(h - 1 - j) * w + i) * 3;
          if (heights) {
            const auto v = static_cast<std::uint8_t>(tile.heightQ[k] >> 8);
            p[0] = p[1] = p[2] = v;
          } else {
            p[0] = static_cast<std::uint8_t>(tile.colourRgba[k]);
            p[1] = static_cast<std::uint8_t>(tile.colourRgba[k] >> 8);
            p[2] = static_cast<std::uint8_t>(tile.colourRgba[k] >> 16);
          }
        }
      }
    }
  }
  auto out = OIIO::ImageOutput::create(output);
  if (!out) throw std::runtime_error(output + ": cannot write this image format: " + OIIO::geterror());
  const OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(output, spec) || !out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close()) {
    throw std::runtime_error(output + ": " + out->geterror());
  }
  std::printf("%s: level %d, %d x %d pixels (north up)\n", output.c_str(), level, w, h);
  return 0;
}

int runLandmarks(int size, double spacing, std::uint64_t seed) {
  BuiltinTerrainSpec spec;
  spec.sizeVox = size;
  spec.spacingM = spacing;
  spec.seed = seed;
  std::printf("built-in terrain %dx%d at %.2f m, seed %llu: x east 0..%.0f m, y north 0..%.0f m\n", size, size, spacing,
              static_cast<unsigned long long>(seed), (size - 1) * spacing, (size - 1) * spacing);
  std::printf("%-18s %9s %9s %8s  %s\n", "name", "x m", "y m", "ground m", "what");
  for (const BuiltinLandmark& m : builtinLandmarks(spec)) {
    std::printf("%-18s %9.0f %9.0f %8.0f  %s\n", m.name.c_str(), m.positionM.x, m.positionM.y, m.groundM,
                m.description.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fieldcast-db: build, inspect, verify and preview Fieldcast terrain databases"};
  app.require_subcommand(1);

  BuildArgs build;
  CLI::App* buildCmd =
      app.add_subcommand("build", "build a database from a DEM (+ orthophoto) or the built-in terrain");
  auto* builtinOpt = buildCmd->add_flag("--builtin", build.builtin, "the built-in terrain");
  auto* demOpt = buildCmd->add_option(
      "--dem", build.dem, "elevation: GeoTIFF/TIFF, 16-bit PNG, ESRI ASCII grid (.asc), raw grid (.raw/.bin)");
  builtinOpt->excludes(demOpt);
  buildCmd->add_option("--ortho", build.ortho, "orthophoto draped over the DEM (any image OpenImageIO reads)")
      ->needs(demOpt);
  buildCmd->add_option("-o,--output", build.output, "database to write")->required();
  buildCmd->add_option("--objects", build.objects, "placement list of objects (CSV: model,x,y,heading,scale)")
      ->check(CLI::ExistingFile);
  buildCmd->add_option("--size", build.size, "built-in: voxels per side")
      ->check(intRange(kMinBuiltinSizeVox, kMaxBuiltinSizeVox, "voxels"))
      ->capture_default_str();
  buildCmd->add_option("--spacing", build.spacing, "built-in: voxel spacing in metres")
      ->check(finiteRange(kMinSpacingM, kMaxSpacingM, "m"))
      ->capture_default_str();
  buildCmd->add_option("--seed", build.seed, "built-in: seed")->check(seedNumber())->capture_default_str();
  buildCmd->add_flag("!--no-objects", build.builtinObjects,
                     "built-in: the bare land, without woods, hedgerows and villages");
  buildCmd
      ->add_option("--dem-spacing", build.demSpacing,
                   "DEM voxel spacing in metres (overrides the file; needed when it does not say)")
      ->check(finiteRange(kMinSpacingM, kMaxSpacingM, "m"));
  buildCmd->add_option("--nodata", build.nodata, "DEM nodata value when the file does not say")->check(finiteNumber());
  buildCmd->add_option("--raw-size", build.rawSize, "raw DEM without sidecar: WxH");
  buildCmd->add_option("--raw-type", build.rawType, "raw DEM without sidecar: int16, uint16 or float32")
      ->check(CLI::IsMember({"int16", "uint16", "float32"}))
      ->capture_default_str();
  buildCmd->add_option("--vertical-scale", build.verticalScale, "DEM: metres per sample count")
      ->check(finiteRange(kMinVerticalScaleM, kMaxVerticalScaleM, "m per count"))
      ->capture_default_str();
  buildCmd->add_option("--vertical-offset", build.verticalOffset, "DEM: metres at sample 0")
      ->check(finiteRange(-kMaxVerticalOffsetM, kMaxVerticalOffsetM, "m"))
      ->capture_default_str();
  buildCmd->add_option("--tile-shift", build.tileShift, "tiles of 2^shift voxels a side")
      ->check(intRange(kMinTileShift, kMaxTileShift, ""))
      ->capture_default_str();
  buildCmd->add_flag("--grey", build.grey, "grey-level database");
  buildCmd->add_option("--threads", build.threads, "worker threads (0: every core)")
      ->check(intRange(0, 1024, "threads"))
      ->capture_default_str();
  buildCmd->add_option("--zstd-level", build.zstdLevel, "zstd compression level (20..22 need much more memory)")
      ->check(intRange(1, 22, ""))
      ->capture_default_str();
  buildCmd->add_option("--sun-azimuth", build.sunAzimuth, "procedural colour: sun azimuth, degrees from north")
      ->check(finiteRange(0.0, 360.0, "degrees"))
      ->capture_default_str();
  buildCmd->add_option("--sun-elevation", build.sunElevation, "procedural colour: sun elevation, degrees")
      ->check(finiteRange(0.0, 90.0, "degrees"))
      ->capture_default_str();

  std::string infoPath;
  CLI::App* infoCmd = app.add_subcommand("info", "print a database's header and levels");
  infoCmd->add_option("database", infoPath)->required();

  std::string verifyPath;
  CLI::App* verifyCmd = app.add_subcommand("verify", "read and check every tile");
  verifyCmd->add_option("database", verifyPath)->required();

  std::string previewPath, previewOut;
  int previewLevel = -1;
  bool previewHeights = false;
  CLI::App* previewCmd = app.add_subcommand("preview", "write one level as an image (north up)");
  previewCmd->add_option("database", previewPath)->required();
  previewCmd->add_option("-o,--output", previewOut, "image to write (PNG, JPEG, TIFF, ...)")->required();
  previewCmd->add_option("--level", previewLevel, "level (default: the finest at most 2048 wide)")
      ->check(intRange(0, 31, ""));
  previewCmd->add_flag("--heights", previewHeights, "grey heights instead of colour");

  int lmSize = 8192;
  double lmSpacing = 2.0;
  std::uint64_t lmSeed = 1;
  CLI::App* landmarksCmd =
      app.add_subcommand("landmarks", "where the built-in terrain's features are, in world metres");
  landmarksCmd->add_option("--size", lmSize, "built-in: voxels per side")
      ->check(intRange(kMinBuiltinSizeVox, kMaxBuiltinSizeVox, "voxels"))
      ->capture_default_str();
  landmarksCmd->add_option("--spacing", lmSpacing, "built-in: voxel spacing in metres")
      ->check(finiteRange(kMinSpacingM, kMaxSpacingM, "m"))
      ->capture_default_str();
  landmarksCmd->add_option("--seed", lmSeed, "built-in: seed")->check(seedNumber())->capture_default_str();

  CLI11_PARSE(app, argc, argv);
  try {
    if (buildCmd->parsed()) {
      if (!build.builtin && build.dem.empty()) throw std::invalid_argument("build: give --builtin or --dem FILE");
      return runBuild(build);
    }
    if (infoCmd->parsed()) return runInfo(infoPath);
    if (verifyCmd->parsed()) return runVerify(verifyPath);
    if (previewCmd->parsed()) return runPreview(previewPath, previewOut, previewLevel, previewHeights);
    if (landmarksCmd->parsed()) return runLandmarks(lmSize, lmSpacing, lmSeed);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-db: %s\n", e.what());
    return 2;
  }
  return 0;
}
