#pragma once
// The service configuration: config/fieldcast.toml, validated. Every key is documented in
// config/README.md; an unknown key, a wrong type or a value out of range is an error naming the
// file, line and key.

#include "ConfigReader.h"

#include <fieldcast/Field.h>
#include <fieldcast/Image.h>
#include <fieldcast/Time.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::app {

/// [terrain]: which database the IG renders.
struct TerrainConfig {
  std::string source = "builtin";      ///< "builtin" or a database file
  std::filesystem::path databasePath;  ///< set when source is a file
  std::filesystem::path cacheDir;      ///< where the built-in terrain is generated once
  int builtinSizeVoxels = 8192;        ///< side of the built-in terrain (power of two)
  std::uint64_t builtinSeed = 1;
  std::int64_t memoryBudgetMiB = 1024;  ///< tile cache budget
};

/// [render]: the image generator.
struct RenderConfig {
  int threads = 0;                    ///< render workers; 0 = one per core
  double maxRateHz = 0.0;             ///< cap on the render rate; 0 = as fast as it can
  double hfovDeg = 60.0;              ///< horizontal field of view of the display window
  double marginFraction = 0.10;       ///< frame margin on each side, fraction of each dimension
  double targetFrameMs = 0.0;         ///< frame-time controller target; 0 = fixed quality
  double quality = 1.0;               ///< pixel-to-voxel ratio knob (larger: coarser and faster)
  double maxAnisotropy = 0.0;         ///< grazing-angle level of detail (RenderSettings); 0 = off
  double controllerAnisotropy = 2.0;  ///< the frame-time controller turns the rule on at this first; 0 = never
  bool rangeImage = false;            ///< render the per-pixel range (needed by the 3D warp)
  bool grey = false;                  ///< render grey-level frames
  int widthPx = 720;                  ///< display window rendered (the output raster by default)
  int heightPx = 486;
};

/// [warp]: the post-rendering processor.
enum class WarpChoice : std::uint8_t { Hold, Quadratic, Homography, Range3d };
struct WarpConfig {
  WarpChoice kind = WarpChoice::Quadratic;
  bool flickerFilter = false;
  bool autoGain = false;
  double leadMs = 4.0;  ///< the field thread wakes this long before a field's display time
};

/// [output]: the video the service emits.
struct OutputConfig {
  RationalRate fieldRate{60000, 1001};
  ScanMode scan = ScanMode::Interlaced;
  FieldOrder fieldOrder = FieldOrder::BottomFirst;  ///< NTSC 486-line video is bottom field first
  int widthPx = 720;
  int heightPx = 486;
  PixelFormat format = PixelFormat::Uyvy422;
};

/// [motion]: what moves the eye point.
enum class MotionChoice : std::uint8_t { Flight, Stick };
struct MotionConfig {
  MotionChoice source = MotionChoice::Flight;
  std::filesystem::path flightPath;             ///< scripted flight (source = "flight")
  std::vector<double> startPose{0, 0, 500, 0};  ///< x, y, z (m), heading (deg) for the stick
  double startSpeedMps = 120.0;
  double durationS = 0.0;  ///< stop after this long; 0 = until a signal
};

/// [sinks.*]: where fields go.
struct Y4mOutput {
  bool enabled = false;
  std::filesystem::path path;  ///< "-" for standard output
  bool chroma420 = true;       ///< 4:2:0 (what most players read) or 4:2:2
};
struct RtpOutput {
  bool enabled = false;
  std::string address = "127.0.0.1";
  int port = 5004;
  int mtu = 1400;
  std::filesystem::path sdpPath;  ///< SDP file describing the stream for receivers; empty: none
};
struct ImageOutput {
  bool enabled = false;
  std::filesystem::path directory;
  int everyNth = 60;
  std::string format = "png";  ///< "png" or "exr"
};
struct WindowOutput {
  bool enabled = false;
};
struct ShmOutput {
  bool enabled = false;
  std::string name = "/fieldcast";
  int slots = 4;
};
struct GpioPulseOutput {
  bool enabled = false;
  std::string chip = "gpiochip0";
  int line = 0;
  double widthUs = 500.0;
};
struct SinksConfig {
  Y4mOutput y4m;
  RtpOutput rtp;
  ImageOutput images;
  WindowOutput window;
  ShmOutput shm;
  GpioPulseOutput gpioPulse;
  std::filesystem::path contactSheet;  ///< PNG of fields through the run, written at exit; empty: none
  int contactSheetFields = 12;
};

/// [input]: the control stick.
struct InputConfig {
  std::string stick;              ///< evdev path or name match; empty: no stick
  std::filesystem::path profile;  ///< stick profile (config/sticks/*.toml); empty: generic
  std::filesystem::path record;   ///< record the input to this file; empty: no recording
  std::string sync;               ///< GPIO line of the external field sync ("gpiochip0:17"); empty: none
};

/// [metrics]: figures.
struct MetricsConfig {
  double logIntervalS = 1.0;
  std::filesystem::path summaryJson;  ///< JSON summary written at exit; empty: none
};

/// [threads]: scheduling.
struct ThreadsConfig {
  bool realtimeFieldThread = true;  ///< ask for SCHED_FIFO for the field thread
  int fieldThreadCpu = -1;          ///< pin the field thread to this CPU; -1: no pinning
};

/// The whole configuration.
struct ServiceConfig {
  std::string sourcePath;
  TerrainConfig terrain;
  RenderConfig render;
  WarpConfig warp;
  OutputConfig output;
  MotionConfig motion;
  SinksConfig sinks;
  InputConfig input;
  MetricsConfig metrics;
  ThreadsConfig threads;
};

/// Reads and validates a configuration file, then applies `overrides` ("table.key=value", as
/// given to --set). Throws ConfigError on the first problem.
ServiceConfig loadServiceConfig(const std::string& path, const std::vector<std::string>& overrides = {});

/// One-paragraph human summary (for --check-config and the start-up log).
std::string describe(const ServiceConfig& config);

}  // namespace fieldcast::app
