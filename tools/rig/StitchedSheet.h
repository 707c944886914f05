#pragma once
// The rig's contact sheet: rows of the channels' fields side by side, left to right in the order
// given, one row per instant (a field number every channel wrote an image of — with a host, made
// from its samples in every channel), the rows spread through the run. Interlaced fields are
// line-doubled to the frame's shape.

#include "ChannelRun.h"

#include <filesystem>
#include <vector>

namespace fieldcast::tools {

struct SheetWritten {
  int rows = 0;
  /// The least contrast of any field on the sheet: the standard deviation of its grey levels
  /// (0–255). A black or blank field has none.
  double leastContrast = 0.0;
};

/// Writes the sheet to `path` (PNG) with at most `rows` rows. Throws std::runtime_error when no
/// field number has an image from every channel, or an image cannot be read or the sheet written.
SheetWritten writeStitchedSheet(const std::vector<ChannelRun>& channels, const std::filesystem::path& path, int rows);

}  // namespace fieldcast::tools
