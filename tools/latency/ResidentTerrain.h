#pragma once
// A terrain database for the evaluation (`fieldcast-latency --db`): opened as the service opens it
// (a tile cache over the file), then every tile of every level loaded and kept, so that the truth
// and the IG's frames are the database at full resolution wherever a flight looks — never a
// coarser level standing in for a tile still on its way, which would be a paging artefact
// scored as a warp error.

#include "EvaluatedFlight.h"
#include "WarpEvaluation.h"

#include <ig_core/TileCache.h>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace fieldcast::tools {

/// Opens the database at `path` and loads all of it within `budgetBytes`. Throws
/// std::runtime_error naming the file: unreadable, a tile that cannot be decoded, or a database
/// larger than the budget (with the budget it would need).
std::unique_ptr<core::TileCache> openResidentDatabase(const std::filesystem::path& path, std::size_t budgetBytes);

/// Where `flight` leaves the terrain's grid during the part `spec` evaluates (one second before the
/// first field to the last), in words; nothing when it stays over it all the way.
std::optional<std::string> whereFlightLeavesTerrain(const EvaluatedFlight& flight, const core::TerrainGeometry& terrain,
                                                    const EvaluationSpec& spec);

}  // namespace fieldcast::tools
