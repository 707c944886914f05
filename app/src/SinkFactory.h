#pragma once
// Builds the SinkHub the configuration asks for ([sinks.*]), plus the demo's contact sheet.

#include "ServiceConfig.h"

#include <io_bridge/SinkHub.h>
#include <io_bridge/StreamFormat.h>
#include <io_bridge/WindowSink.h>

#include <functional>
#include <memory>

namespace fieldcast::app {

/// The output stream the configuration describes ([output]).
io::StreamFormat streamFormatOf(const ServiceConfig& config);

/// The sinks the service talks to after start.
struct Sinks {
  std::unique_ptr<io::SinkHub> hub;
  io::WindowSink* window = nullptr;  ///< owned by the hub; null when [sinks.window] is off
};

/// A hub holding every enabled sink, not yet started. `onKey` receives the live window's keys
/// (for a keyboard flight). Throws std::runtime_error naming the sink and the key when a sink
/// cannot be made (an output folder that cannot be created, no display for the window); sinks
/// that fail to open say so when the hub starts.
Sinks makeSinks(const ServiceConfig& config, const io::StreamFormat& format,
                std::function<void(int code, io::WindowKey key)> onKey = {});

}  // namespace fieldcast::app
