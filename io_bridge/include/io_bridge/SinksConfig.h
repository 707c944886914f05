#pragma once
// The [output] and [sinks.*] sections of the service configuration (keys in config/README.md):
// the stream every sink receives, which sinks are on and how each is set, and the factory that
// makes the SinkHub holding them.

#include <io_bridge/GpioPulseSink.h>
#include <io_bridge/ImageFileSink.h>
#include <io_bridge/RtpVideoSink.h>
#include <io_bridge/SinkHub.h>
#include <io_bridge/StreamFormat.h>
#include <io_bridge/WindowSink.h>
#include <io_bridge/Y4mSink.h>

#include <fieldcast/ConfigReader.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace fieldcast::io {

/// [sinks.shm]: the shared-memory ring.
struct ShmOutput {
  std::string name = "/fieldcast";
  int slots = 4;
};

/// [sinks.gpio_pulse]: a pulse on a GPIO line at every field's display time.
struct GpioPulseOutput {
  std::string chip = "gpiochip0";
  int line = 0;
  GpioPulseOptions pulse;
};

/// [sinks]: each output is present when enabled.
struct SinksConfig {
  std::optional<Y4mSinkOptions> y4m;
  std::optional<RtpVideoSinkOptions> rtp;
  std::optional<ImageFileSinkOptions> images;
  bool window = false;
  std::optional<ShmOutput> shm;
  std::optional<GpioPulseOutput> gpioPulse;
  std::filesystem::path contactSheet;  ///< PNG of fields through the run, written at exit; empty: none
  int contactSheetFields = 12;
};

/// Reads [output] (rate, scan, field_order, width, height, format) into a validated stream
/// format with the pixel aspect its size implies. Throws ConfigError.
StreamFormat readStreamFormat(ConfigReader& table);

/// Reads [sinks] and its tables. Throws ConfigError.
SinksConfig readSinksConfig(ConfigReader& table);

/// The sinks a channel talks to after start.
struct Sinks {
  std::unique_ptr<SinkHub> hub;
  WindowSink* window = nullptr;  ///< owned by the hub; null when the window is off
};

/// A hub holding every enabled sink, not yet started. `onKey` receives the live window's keys
/// (for a keyboard flight). Throws std::runtime_error naming the sink and the key when a sink
/// cannot be made (an output folder that cannot be created, no display for the window); sinks
/// that fail to open say so when the hub starts.
Sinks makeSinks(const SinksConfig& config, const StreamFormat& format,
                std::function<void(int code, WindowKey key)> onKey = {});

}  // namespace fieldcast::io
