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
  RenderSettings settings;               ///< quality, grazing rule, margin, range image, colour, haze
  FrameTimeControllerConfig controller;  ///< target 0: fixed quality
  /// visibility_m was given (it is then settings.hazeRangeM); otherwise the service sets the haze
  /// range from the database's extent (defaultVisibilityM).
  bool visibilityGiven = false;
};

/// The haze range for a database `extentM` across (its longer side): three quarters of it, so
/// the far edge seen from one side is in haze but the whole database can be seen from above;
/// at least 3 km, so a small database is not greyed out. The built-in 16 km terrain gets 12.3 km.
double defaultVisibilityM(double extentM) noexcept;

/// Reads [render]; the display window defaults to `defaultWidthPx` × `defaultHeightPx` (the
/// output raster). Throws ConfigError.
RenderConfig readRenderConfig(ConfigReader& table, int defaultWidthPx, int defaultHeightPx);

}  // namespace fieldcast::core
