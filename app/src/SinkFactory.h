#pragma once
// Builds the SinkHub the configuration asks for ([sinks.*]), plus the demo's contact sheet.

#include "ServiceConfig.h"

#include <io_bridge/SinkHub.h>
#include <io_bridge/StreamFormat.h>

#include <memory>

namespace fieldcast::app {

/// The output stream the configuration describes ([output]).
io::StreamFormat streamFormatOf(const ServiceConfig& config);

/// A hub holding every enabled sink, not yet started. Throws std::runtime_error naming the sink
/// and the key when a sink cannot be made (an output folder that cannot be created, say); sinks
/// that fail to open say so when the hub starts.
std::unique_ptr<io::SinkHub> makeSinks(const ServiceConfig& config, const io::StreamFormat& format);

}  // namespace fieldcast::app
