#pragma once
// The [render] section of the service configuration (keys in config/README.md): the render pool,
// the pacing of the render loop, the frame-time controller, the renderer's settings and the
// display window a channel renders.

#include <ig_core/FrameTimeController.h>
#include <ig_core/RenderSettings.h>

#include <fieldcast/ConfigReader.h>

namespace fieldcast::core {

/// What [render] sets.
struct RenderConfig {
  int threads = 0;         ///< render workers; 0 = one per core
  double maxRateHz = 0.0;  ///< cap on the render rate; 0 = as fast as it can
  double hfovDeg = 60.0;   ///< horizontal field of view of the display window
  int widthPx = 720;       ///< display window rendered (the output raster by default)
  int heightPx = 486;
  RenderSettings settings;               ///< quality, grazing rule, margin, range image, colour
  FrameTimeControllerConfig controller;  ///< target 0: fixed quality
};

/// Reads [render]; the display window defaults to `defaultWidthPx` × `defaultHeightPx` (the
/// output raster). Throws ConfigError.
RenderConfig readRenderConfig(ConfigReader& table, int defaultWidthPx, int defaultHeightPx);

}  // namespace fieldcast::core
