#pragma once
// The [warp] section of the service configuration (keys in config/README.md): which warp, the
// field post-processing, and how early the field thread wakes. The output raster and field rate
// are the [output] section's; the channel that owns the PRP fills those in.

#include <prp_warp/FieldWarper.h>

#include <fieldcast/ConfigReader.h>
#include <fieldcast/Time.h>

#include <chrono>

namespace fieldcast::warp {

/// What [warp] sets.
struct PrpSettings {
  FieldWarperConfig warper;  ///< warp kind, flicker filter, AGC; raster and format come from [output]
  Nanoseconds lead{
      std::chrono::microseconds(4000)};  ///< the field thread wakes this long before a field's display time
};

/// Reads [warp] (kind, flicker_filter, auto_gain, lead_ms). Throws ConfigError.
PrpSettings readPrpSettings(ConfigReader& table);

}  // namespace fieldcast::warp
