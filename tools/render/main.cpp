// fieldcast-render: renders one frame for a pose and writes it as a PNG (and optionally the range
// image as a 32-bit float TIFF/EXR), with the frame's figures on stdout.
//
//   fieldcast-render --db builtin --pose 8192,8192,300,45,-20,0 --agl --fov 60 --size 720x486 --out f.png
//
// --db builtin renders the built-in terrain (generated into the cache folder on first use), --db
// PATH a database made by fieldcast-db, --db synthetic the small procedural hills of the tests.
#include <tools/OptionChecks.h>

#include <ig_core/OpenTerrain.h>
#include <ig_core/Renderer.h>
#include <ig_core/SyntheticTerrain.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/ToolMain.h>

#include <OpenImageIO/imageio.h>
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace fieldcast;
using namespace fieldcast::tools;

/// Where each pose component may lie. Beyond ±10 000 km or 1000 km up the terrain is out of sight
/// and double metres lose the centimetres the renderer needs.
struct PoseLimit {
  const char* name;
  double min, max;
  const char* unit;
};
constexpr std::array<PoseLimit, 6> kPoseLimits{{{"x", -1e7, 1e7, "m"},
                                                {"y", -1e7, 1e7, "m"},
                                                {"z", -1e4, 1e6, "m"},
                                                {"heading", -360.0, 360.0, "degrees"},
                                                {"pitch", -90.0, 90.0, "degrees"},
                                                {"roll", -180.0, 180.0, "degrees"}}};

std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* what) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::runtime_error(std::string("--") + what + ": '" + item + "' is not a number");
    }
  }
  if (values.size() != count) {
    throw std::runtime_error(std::string("--") + what + ": expected " + std::to_string(count) +
                             " comma-separated numbers, got '" + text + "'");
  }
  return values;
}

/// The pose from --pose, every component finite and within kPoseLimits.
std::vector<double> parsePose(const std::string& text) {
  const std::vector<double> p = parseNumbers(text, kPoseLimits.size(), "pose");
  for (std::size_t i = 0; i < p.size(); ++i) {
    const PoseLimit& l = kPoseLimits[i];
    if (!(p[i] >= l.min && p[i] <= l.max)) {  // false for NaN too
      throw std::runtime_error("--pose: " + std::string(l.name) + " must be a finite number from " +
                               formatNumber(l.min) + " to " + formatNumber(l.max) + " " + l.unit + ", got '" +
                               formatNumber(p[i]) + "'");
    }
  }
  return p;
}

/// Refuses an output whose folder does not exist or cannot be written, before rendering.
void checkOutputFolder(const std::string& option, const std::string& output) {
  namespace fs = std::filesystem;
  const fs::path path(output);
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw std::runtime_error(option + " " + output + ": is a folder; expected a file name");
  if (!fs::is_directory(folder, ec)) {
    throw std::runtime_error(option + " " + output + ": folder " + folder.string() + " does not exist");
  }
  if (::access(folder.c_str(), W_OK | X_OK) != 0) {
    throw std::runtime_error(option + " " + output + ": cannot write in " + folder.string() + ": " +
                             std::strerror(errno));
  }
}

/// Writes a set of images all or nothing: each goes to a temporary in its target's folder (same
/// extension, so OpenImageIO picks the same format); only when every one was written are they
/// renamed into place. A failure removes the temporaries and leaves any earlier files untouched.
class ImageSetWriter {
 public:
  ImageSetWriter() = default;
  ImageSetWriter(const ImageSetWriter&) = delete;
  ImageSetWriter& operator=(const ImageSetWriter&) = delete;
  ~ImageSetWriter() {
    std::error_code ec;
    for (const Pending& p : mPending) std::filesystem::remove(p.temp, ec);
  }

  /// Writes `pixels` to a temporary for `path`. Throws naming `path` (never the temporary).
  void write(const std::string& path, int w, int h, int channels, OIIO::TypeDesc type, const void* pixels) {
    const std::filesystem::path target(path);
    std::filesystem::path temp = target;
    temp.replace_filename("." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                          target.extension().string());
    mPending.push_back({temp, target});  // removed on failure from here on
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw std::runtime_error(path + ": cannot write this format (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec spec(w, h, channels, type);
    if (!out->open(temp.string(), spec) || !out->write_image(type, pixels) || !out->close()) {
      std::string why = out->geterror();
      if (const std::size_t at = why.find(temp.string()); at != std::string::npos)
        why.replace(at, temp.string().size(), path);
      throw std::runtime_error(path + ": " + why);
    }
  }

  /// Renames every temporary into place. On a failed rename, the files already renamed are
  /// removed again so no partial set is left.
  void commit() {
    std::vector<std::filesystem::path> done;
    for (const Pending& p : mPending) {
      std::error_code ec;
      std::filesystem::rename(p.temp, p.target, ec);
      if (ec) {
        for (const auto& d : done) std::filesystem::remove(d, ec);
        throw std::runtime_error(p.target.string() + ": " + ec.message());
      }
      done.push_back(p.target);
    }
    mPending.clear();
  }

 private:
  struct Pending {
    std::filesystem::path temp, target;
  };
  std::vector<Pending> mPending;
};

int run(int argc, char** argv) {
  CLI::App app{"Render one frame of the terrain for a pose (PNG)."};
  std::string poseText;
  double fovDeg = 60.0;
  std::string sizeText = "720x486";
  std::string outPath;
  std::string rangePath;
  bool agl = false;
  bool displayOnly = false;
  std::string db = "builtin";
  std::string cacheDir;
  int terrainSize = 0;
  unsigned seed = 0;
  core::RenderSettings settings;
  bool grey = false;
  int threads = 0;
  int repeat = 1;
  app.add_option("--pose", poseText, "x,y,z,heading,pitch,roll: metres east, north, up; degrees")->required();
  app.add_flag("--agl", agl, "z is the height above the ground under (x, y), not above datum");
  app.add_option("--fov", fovDeg, "horizontal field of view of the display window, degrees")
      ->check(finiteRange(1.0, 170.0, "degrees"));
  app.add_option("--size", sizeText, "display window WxH in pixels (the frame adds the margins)");
  app.add_option("--out", outPath, "PNG (or any format OpenImageIO writes) for the frame")->required();
  app.add_option("--range-out", rangePath, "also write the range image (float metres, e.g. .exr or .tif)");
  app.add_flag("--display-only", displayOnly,
               "write only the display window, without the margins (unrolled: with roll its corners lie outside the "
               "turned window the frame renders, and repeat their columns' end pixels)");
  app.add_option("--margin", settings.marginFraction, "margin per side, fraction of each dimension")
      ->check(finiteRange(0.0, 1.0, "of each dimension"));
  app.add_option("--quality", settings.quality, "pixel-to-voxel ratio (LOD bias = log2); larger is coarser and faster")
      ->check(finiteRange(0.05, 64.0, ""));
  app.add_option("--anisotropy", settings.maxAnisotropy,
                 "grazing-angle level of detail: footprint elongation allowed before a coarser level (0 = depth alone)")
      ->check(finiteRange(0.0, 1000.0, ""));
  app.add_option("--supersample", settings.verticalSupersample, "vertical sub-rays per pixel")
      ->check(intRange(1, 4, "sub-rays"));
  app.add_flag("--grey", grey, "grey-level frame");
  app.add_option("--haze", settings.hazeRangeM, "range (m) where haze covers 63%; 0 = none")
      ->check(finiteRange(0.0, 1e7, "m"));
  app.add_option("--threads", threads, "render workers (0: one per core)")->check(intRange(0, 1024, "threads"));
  app.add_option("--repeat", repeat, "render the frame this many times and report the median time")
      ->check(intRange(1, 100000, ""));
  app.add_option("--db", db, "terrain: 'builtin', a database path, or 'synthetic' (procedural test hills)");
  app.add_option("--cache-dir", cacheDir, "cache folder of the built-in terrain (default: ~/.cache/fieldcast)");
  app.add_option("--terrain-size", terrainSize,
                 "voxels per side of the built-in (default 8192) or synthetic (default 4096) terrain, 2 m spacing")
      ->check(intRange(64, 16384, "voxels"));
  app.add_option("--seed", seed, "terrain seed (built-in default 1, synthetic default 11)")
      ->check(intRange(0, 4294967295LL, ""));
  CLI11_PARSE(app, argc, argv);

  const std::vector<double> p = parsePose(poseText);
  int w = 0;
  int h = 0;
  int used = 0;
  if (std::sscanf(sizeText.c_str(), "%dx%d%n", &w, &h, &used) != 2 ||
      static_cast<std::size_t>(used) != sizeText.size() || w < 2 || h < 2 || w > 16384 || h > 16384) {
    throw std::runtime_error("--size: expected WxH such as 720x486, W and H from 2 to 16384 pixels, got '" + sizeText +
                             "'");
  }
  settings.colourMode = grey ? core::FrameColour::Grey : core::FrameColour::Rgb;
  settings.rangeImage = !rangePath.empty();
  checkOutputFolder("--out", outPath);
  if (!rangePath.empty()) checkOutputFolder("--range-out", rangePath);
  if (!rangePath.empty() &&
      std::filesystem::path(rangePath).lexically_normal() == std::filesystem::path(outPath).lexically_normal()) {
    throw std::runtime_error("--range-out: names the same file as --out (" + outPath + ")");
  }

  core::ViewRequest request;
  request.pose.headingRad = radians(p[3]);
  request.pose.pitchRad = radians(p[4]);
  request.pose.rollRad = radians(p[5]);
  request.display = Intrinsics::fromHorizontalFov(w, h, radians(fovDeg));

  std::unique_ptr<core::MemoryTerrain> synthetic;
  std::unique_ptr<core::TileCache> cache;
  const core::TerrainView* view = nullptr;
  if (db == "synthetic") {
    synthetic = core::makeSyntheticTerrain(
        {core::SyntheticKind::Hills, terrainSize > 0 ? terrainSize : 4096, 2.0, 8, seed > 0 ? seed : 11u});
    view = &synthetic->view();
  } else {
    core::BuiltinTerrainSpec spec;
    if (terrainSize > 0) spec.sizeVox = terrainSize;
    if (seed > 0) spec.seed = seed;
    cache = core::openTerrain(db, cacheDir, std::size_t{1} << 30, spec);
    view = &cache->view();
  }
  request.pose.positionM = {p[0], p[1], p[2] + (agl ? view->heightAtM(p[0], p[1]) : 0.0)};
  if (cache) {
    // One frame, no hurry: page in what this view needs before rendering it.
    const core::FrameLayout layout = core::layoutFrame(request.display, settings.marginFraction, request.pose.rollRad);
    cache->prefetch(request.pose, glm::dvec3{0.0}, layout.frame, core::prefetchLod(settings));
    cache->waitIdle(std::chrono::seconds(60));
    request.pose.positionM.z = p[2] + (agl ? view->heightAtM(p[0], p[1]) : 0.0);
  }

  core::Renderer renderer(*view, settings, threads);
  core::RenderStats stats;
  core::FrameLease lease;
  if (cache) lease = cache->lease();  // tiles stay alive while the frame reads them
  Frame frame;
  std::vector<double> times;
  for (int n = 0; n < repeat; ++n) {
    frame = renderer.render(request, &stats, std::move(frame));
    times.push_back(std::chrono::duration<double, std::milli>(frame.renderEnd - frame.renderStart).count());
  }
  lease.release();
  std::sort(times.begin(), times.end());
  const double ms = times[times.size() / 2];

  const int channels = grey ? 1 : 3;
  const int x0 = displayOnly ? frame.margin.x : 0;
  const int y0 = displayOnly ? frame.margin.y : 0;
  const int outW = displayOnly ? frame.displayWidthPx() : frame.image.widthPx();
  const int outH = displayOnly ? frame.displayHeightPx() : frame.image.heightPx();
  std::vector<std::uint8_t> pixels;
  pixels.reserve(static_cast<std::size_t>(outW * outH * channels));
  for (int y = y0; y < y0 + outH; ++y) {
    const std::uint8_t* row = frame.image.row(y) + x0 * channels;
    pixels.insert(pixels.end(), row, row + outW * channels);
  }
  // Frame and range image land together or not at all: a failed range image leaves no PNG behind.
  ImageSetWriter images;
  images.write(outPath, outW, outH, channels, OIIO::TypeDesc::UINT8, pixels.data());
  if (!rangePath.empty()) {
    std::vector<float> range;
    for (int y = y0; y < y0 + outH; ++y) {
      const float* row = frame.rangeM.data() + static_cast<std::size_t>(y) * frame.image.widthPx() + x0;
      range.insert(range.end(), row, row + outW);
    }
    images.write(rangePath, outW, outH, 1, OIIO::TypeDesc::FLOAT, range.data());
  }
  images.commit();
  std::printf("wrote %s: %dx%d (display %dx%d, margin %d,%d), %.2f ms (median of %d) on %d threads, %.2f steps/px\n",
              outPath.c_str(), outW, outH, frame.displayWidthPx(), frame.displayHeightPx(), frame.margin.x,
              frame.margin.y, ms, repeat, renderer.threads(),
              static_cast<double>(stats.steps) / static_cast<double>(stats.pixels));
  if (!rangePath.empty()) std::printf("wrote %s: range in metres (inf = sky)\n", rangePath.c_str());
  if (cache) {
    const core::TileCacheStats st = cache->stats();
    std::printf("terrain: %llu tiles resident, %llu samples answered by a coarser level (tile not resident)\n",
                static_cast<unsigned long long>(st.residentTiles), static_cast<unsigned long long>(st.viewMisses));
  }
  for (const ControlPoint& cp : frame.controlPoints) {
    const char* kind = cp.kind == ControlPointKind::Surface ? "surface"
                       : cp.kind == ControlPointKind::Sky   ? "sky"
                                                            : "missing";
    std::printf("control (%.1f, %.1f): %s %.3f %.3f %.3f\n", cp.framePx.x, cp.framePx.y, kind, cp.world.x, cp.world.y,
                cp.world.z);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fieldcast::runProgram("fieldcast-render", run, argc, argv); }
