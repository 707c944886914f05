#pragma once
// The service configuration: config/fieldcast.toml, validated. Composition only: each module
// reads its own section into its own settings (ig_core [terrain] and [render], prp_warp [warp],
// io_bridge [output], [sinks] and [input], motion [motion]); the service reads [view], [host],
// [metrics] and [threads]. Every key is documented in config/README.md; an unknown key, a wrong type or a
// value out of range is an error naming the file, line and key.

#include <ig_core/Georeference.h>
#include <ig_core/RenderConfig.h>
#include <ig_core/TerrainConfig.h>
#include <io_bridge/FieldLockLink.h>
#include <io_bridge/HostLink.h>
#include <io_bridge/InputConfig.h>
#include <io_bridge/SinksConfig.h>
#include <io_bridge/StreamFormat.h>
#include <motion/HostMotion.h>
#include <motion/MotionConfig.h>
#include <prp_warp/PrpSettings.h>

#include <fieldcast/ConfigReader.h>
#include <fieldcast/Conventions.h>

#include <fieldcast/Intrinsics.h>

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace fieldcast::app {

using fieldcast::ConfigError;

/// [metrics]: figures.
struct MetricsConfig {
  double logIntervalS = 1.0;
  std::filesystem::path summaryJson;  ///< JSON summary written at exit; empty: none
  std::filesystem::path fieldLog;     ///< per-field CSV record (FieldLog); empty: none
};

/// [[host.database]]: a database the host may load by its number (IG Control).
struct HostDatabase {
  std::int8_t number = 0;       ///< 1 to 127
  core::TerrainConfig terrain;  ///< read like [terrain]
};

/// [[host.entity_model]]: the model drawn for a CIGI entity type.
struct HostEntityModel {
  std::uint16_t type = 0;       ///< Entity Control's entity type
  std::filesystem::path model;  ///< a .vox file
  double scale = 1.0;           ///< a voxel is 0.5 m × scale
};

/// [host]: the CIGI host link, used when motion.source = "host".
struct HostConfig {
  io::HostLinkConfig link;
  motion::HostMotionOptions motion;
  std::int8_t databaseNumber = 1;                             ///< the number of [terrain], loaded at start
  std::vector<HostDatabase> databases;                        ///< the others the host may load
  core::GeodeticOrigin origin = core::kBuiltinTerrainOrigin;  ///< world (0, 0) of a database without a CRS
  std::uint16_t viewId = 0;                                   ///< the view View Control addresses as this IG's
  std::uint8_t viewGroup = 0;                                 ///< the view group it belongs to (0: none)
  std::vector<HostEntityModel> entityModels;                  ///< what the host's entities look like, by type
  double celestialUtcOffsetH = 0.0;  ///< Celestial Sphere Control's hour and minute are local time this far east of UTC
};

/// [threads]: scheduling.
struct ThreadsConfig {
  bool realtimeFieldThread = true;  ///< ask for SCHED_FIFO for the field thread
  bool realtimeHostThread = true;   ///< ask for SCHED_FIFO (below the field thread) for the CIGI link's thread
  int fieldThreadCpu = -1;          ///< pin the field thread to this CPU; -1: no pinning
};

/// Which eye of a stereo pair a channel shows.
enum class Eye { Centre, Left, Right };

/// [view]: the channel's eye on the ownship and its display window (README, "Channels").
struct ViewConfig {
  ViewOffset offset;  ///< from the ownship (a stereo pair's head: each eye sits beside it)
  /// The display window's angles from the view axis (left and bottom negative); none: [render]
  /// fov_deg, centred, square pixels.
  std::optional<FrustumAngles> frustum;
  Eye eye = Eye::Centre;
  double eyeSeparationM = 0.064;  ///< interpupillary distance
  /// Distance of zero parallax (the screen's, for a display at a distance); infinite: the eyes'
  /// axes parallel (a collimated display).
  double convergenceM = std::numeric_limits<double>::infinity();
};

/// The whole configuration.
struct ServiceConfig {
  std::string sourcePath;
  core::TerrainConfig terrain;
  core::RenderConfig render;
  ViewConfig view;
  warp::PrpSettings warp;
  io::StreamFormat output;
  motion::MotionConfig motion;
  HostConfig host;
  io::FieldLockConfig lock;  ///< [lock]: the software frame lock with the other channels
  io::SinksConfig sinks;
  io::InputConfig input;
  MetricsConfig metrics;
  ThreadsConfig threads;
};

/// Reads and validates a configuration file, then applies `overrides` ("table.key=value", as
/// given to --set). Throws ConfigError on the first problem.
ServiceConfig loadServiceConfig(const std::string& path, const std::vector<std::string>& overrides = {});

/// One-paragraph human summary (for --check-config and the start-up log).
std::string describe(const ServiceConfig& config);

}  // namespace fieldcast::app
